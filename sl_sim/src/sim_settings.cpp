#include "sl_sim/sim_settings.h"

#include <cmath>
#include <functional>
#include <stdexcept>

namespace sl_sim
{

namespace
{
// One accessor per field, in declaration order: name, kind, unit, description, and a reference getter.
struct Field
{
  SimSettingInfo info;
  std::function<double&(SimSettings&)> d;  // double fields
  std::function<int&(SimSettings&)> i;     // int fields
  std::function<bool&(SimSettings&)> b;    // bool fields
};

// A setting's Field; the accessor's type gives the kind.
Field makeField(const char* name, const char* unit, const char* desc, double& (*get)(SimSettings&))
{
  return Field{ SimSettingInfo{ name, SimSettingInfo::Kind::Double, unit, desc }, get, nullptr, nullptr };
}
Field makeField(const char* name, const char* unit, const char* desc, int& (*get)(SimSettings&))
{
  return Field{ SimSettingInfo{ name, SimSettingInfo::Kind::Int, unit, desc }, nullptr, get, nullptr };
}
Field makeField(const char* name, const char* unit, const char* desc, bool& (*get)(SimSettings&))
{
  return Field{ SimSettingInfo{ name, SimSettingInfo::Kind::Bool, unit, desc }, nullptr, nullptr, get };
}
#define SL_FIELD(field, unit, desc) \
  makeField(#field, unit, desc, [](SimSettings& s) -> decltype((s.field)) { return s.field; })

const std::vector<Field>& fields()
{
  static const std::vector<Field> table = {
    SL_FIELD(projector_power, "",
             "irradiance of a white projector pixel at the projector focus distance, normal incidence"),
    SL_FIELD(projector_black_level, "", "irradiance of a black projector pixel relative to a white one"),
    SL_FIELD(projector_vignetting, "", "projector irradiance at the frame corners relative to the centre"),
    SL_FIELD(ambient, "", "ambient irradiance, in units of projector_power"),
    SL_FIELD(projector_focus_distance, "m", "projector focus distance (0: the rig's)"),
    SL_FIELD(projector_f_number, "", "projector lens f-number (0: the rig's)"),
    SL_FIELD(projector_pixel_size, "m", "projector mirror pitch (0: the rig's)"),
    SL_FIELD(projector_base_blur, "projector px", "projector blur at focus (Gaussian sigma)"),
    SL_FIELD(camera_focus_distance, "m", "camera focus distance (0: the rig's)"),
    SL_FIELD(camera_f_number, "", "camera lens f-number (0: the rig's)"),
    SL_FIELD(camera_pixel_size, "m", "camera pixel pitch (0: the rig's)"),
    SL_FIELD(camera_base_blur, "camera px", "camera blur at focus (Gaussian sigma)"),
    SL_FIELD(defocus_scale, "", "factor on both lenses' defocus blur (1: the rig's optics as they are)"),
    SL_FIELD(defocus, "", "thin-lens defocus blur of projector and camera"),
    SL_FIELD(shadows, "", "projector shadows: points the projector cannot see get no pattern"),
    SL_FIELD(irradiance_falloff, "", "projector irradiance falls with distance squared and incidence cosine"),
    SL_FIELD(antialias, "rays", "rays per edge pixel: 1 (off), 4 or 16"),
    SL_FIELD(vignetting, "", "image-corner illumination relative to the centre"),
    SL_FIELD(glare, "", "fraction of light scattered into a wide halo (sigma 10 px)"),
    SL_FIELD(exposure, "", "gain from scene radiance to sensor full scale"),
    SL_FIELD(full_well, "e-", "electrons at full scale (shot noise)"),
    SL_FIELD(read_noise, "DN", "read noise (8-bit scale, before gamma)"),
    SL_FIELD(noise, "", "shot and read noise on"),
    SL_FIELD(gamma, "", "output = 255 * signal^(1/gamma)"),
  };
  return table;
}
#undef SL_FIELD

const Field& field(const std::string& name)
{
  for (const Field& f : fields())
    if (f.info.name == name)
      return f;
  throw std::invalid_argument(name + ": unknown simulator setting");
}

void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}

bool finitePositive(double v)
{
  return std::isfinite(v) && v > 0.0;
}

bool nonNegative(double v)
{
  return std::isfinite(v) && v >= 0.0;
}

bool inRange(double v, double lo, double hi)
{
  return std::isfinite(v) && v >= lo && v <= hi;
}
}  // namespace

const std::vector<SimSettingInfo>& simSettingsInfo()
{
  static const std::vector<SimSettingInfo> infos = []
  {
    std::vector<SimSettingInfo> v;
    for (const Field& f : fields())
      v.push_back(f.info);
    return v;
  }();
  return infos;
}

void setSimSetting(SimSettings& settings, const std::string& name, double value)
{
  const Field& f = field(name);
  switch (f.info.kind)
  {
    case SimSettingInfo::Kind::Double:
      f.d(settings) = value;
      break;
    case SimSettingInfo::Kind::Int:
      require(std::isfinite(value) && std::abs(value) < 1e9, name + ": must be an integer");
      f.i(settings) = static_cast<int>(std::lround(value));
      break;
    case SimSettingInfo::Kind::Bool:
      f.b(settings) = value != 0.0;
      break;
  }
}

double getSimSetting(const SimSettings& settings, const std::string& name)
{
  const Field& f = field(name);
  SimSettings& s = const_cast<SimSettings&>(settings);  // the accessors only read here
  switch (f.info.kind)
  {
    case SimSettingInfo::Kind::Double:
      return f.d(s);
    case SimSettingInfo::Kind::Int:
      return f.i(s);
    case SimSettingInfo::Kind::Bool:
    default:
      return f.b(s) ? 1.0 : 0.0;
  }
}

void SimSettings::validate() const
{
  require(nonNegative(projector_power), "projector_power: must be >= 0");
  require(inRange(projector_black_level, 0.0, 1.0), "projector_black_level: must be in 0..1");
  require(finitePositive(projector_vignetting) && projector_vignetting <= 1.0,
          "projector_vignetting: must be in (0, 1]");
  require(nonNegative(ambient), "ambient: must be >= 0");
  require(nonNegative(projector_focus_distance), "projector_focus_distance: must be > 0 m (0: the rig's)");
  require(nonNegative(projector_f_number), "projector_f_number: must be > 0 (0: the rig's)");
  require(nonNegative(projector_pixel_size) && projector_pixel_size < 1e-3,
          "projector_pixel_size: must be a pitch in metres, < 1 mm (0: the rig's)");
  require(inRange(projector_base_blur, 0.0, 20.0), "projector_base_blur: must be in 0..20 px");
  require(nonNegative(camera_focus_distance), "camera_focus_distance: must be > 0 m (0: the rig's)");
  require(nonNegative(camera_f_number), "camera_f_number: must be > 0 (0: the rig's)");
  require(nonNegative(camera_pixel_size) && camera_pixel_size < 1e-3,
          "camera_pixel_size: must be a pitch in metres, < 1 mm (0: the rig's)");
  require(inRange(defocus_scale, 0.0, 100.0), "defocus_scale: must be in 0..100");
  require(inRange(camera_base_blur, 0.0, 20.0), "camera_base_blur: must be in 0..20 px");
  require(antialias == 1 || antialias == 4 || antialias == 16, "antialias: must be 1, 4 or 16");
  require(finitePositive(vignetting) && vignetting <= 1.0, "vignetting: must be in (0, 1]");
  require(inRange(glare, 0.0, 0.5), "glare: must be in 0..0.5");
  require(nonNegative(exposure), "exposure: must be >= 0");
  require(finitePositive(full_well), "full_well: must be > 0 electrons");
  require(nonNegative(read_noise), "read_noise: must be >= 0 DN");
  require(finitePositive(gamma) && gamma <= 10.0, "gamma: must be in (0, 10]");
}

}  // namespace sl_sim
