// Simulator settings: defaults, validation naming the field, access by name.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "sl_sim/sim_settings.h"

namespace sl_sim
{

TEST(SimSettings, DefaultsAreValid)
{
  EXPECT_NO_THROW(SimSettings().validate());
}

TEST(SimSettings, EveryFieldIsListedOnceAndReadableByName)
{
  const SimSettings d;
  std::set<std::string> names;
  for (const SimSettingInfo& info : simSettingsInfo())
  {
    EXPECT_TRUE(names.insert(info.name).second) << info.name;
    EXPECT_FALSE(info.description.empty()) << info.name;
    EXPECT_NO_THROW(getSimSetting(d, info.name)) << info.name;
  }
  for (const char* n : { "ambient", "noise", "exposure", "gamma", "antialias", "defocus", "vignetting", "glare",
                         "full_well", "read_noise", "projector_power", "projector_black_level", "projector_f_number",
                         "camera_f_number", "projector_focus_distance", "camera_focus_distance", "defocus_scale" })
    EXPECT_EQ(names.count(n), 1u) << n;
  EXPECT_DOUBLE_EQ(getSimSetting(d, "ambient"), d.ambient);
  EXPECT_DOUBLE_EQ(getSimSetting(d, "noise"), 1.0);
  EXPECT_DOUBLE_EQ(getSimSetting(d, "antialias"), 4.0);
}

TEST(SimSettings, SetByName)
{
  SimSettings s;
  setSimSetting(s, "ambient", 0.3);
  EXPECT_DOUBLE_EQ(s.ambient, 0.3);
  setSimSetting(s, "noise", 0.0);
  EXPECT_FALSE(s.noise);
  setSimSetting(s, "antialias", 16.2);
  EXPECT_EQ(s.antialias, 16);
  EXPECT_THROW(setSimSetting(s, "brightness", 1.0), std::invalid_argument);
  EXPECT_THROW(getSimSetting(s, "brightness"), std::invalid_argument);
}

TEST(SimSettings, InvalidValuesNameTheField)
{
  struct Case
  {
    const char* name;
    double value;
  };
  const Case cases[] = { { "ambient", -0.1 },
                         { "projector_black_level", 1.5 },
                         { "projector_vignetting", 0.0 },
                         { "projector_focus_distance", -0.5 },
                         { "projector_f_number", -1.0 },
                         { "projector_pixel_size", 0.01 },
                         { "camera_f_number", -1.0 },
                         { "camera_pixel_size", -1e-6 },
                         { "defocus_scale", -0.5 },
                         { "camera_base_blur", -1.0 },
                         { "antialias", 3.0 },
                         { "vignetting", 1.2 },
                         { "glare", 0.9 },
                         { "exposure", -1.0 },
                         { "full_well", 0.0 },
                         { "read_noise", -0.5 },
                         { "gamma", 0.0 } };
  for (const Case& c : cases)
  {
    SimSettings s;
    setSimSetting(s, c.name, c.value);
    try
    {
      s.validate();
      ADD_FAILURE() << c.name << " = " << c.value << " accepted";
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_EQ(std::string(e.what()).rfind(std::string(c.name) + ":", 0), 0u) << e.what();
    }
  }
}

}  // namespace sl_sim
