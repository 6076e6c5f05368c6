// AravisSource against Aravis' own simulated GenICam camera ("Fake_1"); built only with libaravis.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "sl_camera/camera/aravis_source.h"

using sl_camera::AravisSource;
using sl_camera::CameraError;
using sl_camera::Frame;
using sl_camera::GrabStatus;
using sl_camera::SourceSettings;

namespace
{
GrabStatus grabNext(AravisSource& source, Frame& frame)
{
  for (int i = 0; i < 100; ++i)  // up to 100 x 100 ms: generous
  {
    const GrabStatus s = source.grab(frame, std::chrono::milliseconds(100));
    if (s != GrabStatus::Timeout)
      return s;
  }
  return GrabStatus::Timeout;
}
}  // namespace

TEST(CameraAravis, StreamsMono8FromTheFakeCameraWithSettingsApplied)
{
  SourceSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.rate = 50.0;
  settings.exposure = 0.002;
  settings.gain = 3.0;
  AravisSource source("Fake_1", settings);
  EXPECT_EQ(source.description(), "Aravis camera Fake_1");
  source.open();
  ASSERT_TRUE(source.isOpen());
  EXPECT_NEAR(source.nominalRate(), 50.0, 0.5);
  for (const std::string& w : source.takeWarnings())
    ADD_FAILURE() << "unexpected warning: " << w;

  Frame frame;
  std::uint64_t previous = 0;
  for (int i = 0; i < 3; ++i)
  {
    ASSERT_EQ(grabNext(source, frame), GrabStatus::Frame);
    ASSERT_EQ(frame.image.type(), CV_8UC1);
    EXPECT_EQ(frame.image.cols, 64);
    EXPECT_EQ(frame.image.rows, 48);
    EXPECT_TRUE(frame.has_sequence);
    if (i > 0)
    {
      EXPECT_GT(frame.sequence, previous);
    }
    previous = frame.sequence;
    EXPECT_GT(frame.stamp.time_since_epoch().count(), 0);
  }
  source.close();
  EXPECT_FALSE(source.isOpen());
  // One source can be opened again (what the capture thread does after a loss).
  source.open();
  ASSERT_EQ(grabNext(source, frame), GrabStatus::Frame);
  source.close();
}

TEST(CameraAravis, OutOfRangeSettingsAreClampedWithAWarning)
{
  SourceSettings settings;
  settings.gain = 50.0;  // the fake camera's GainRaw goes to 10 (no unit)
  AravisSource source("Fake_1", settings);
  source.open();
  const auto warnings = source.takeWarnings();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("gain 50 outside 0..10 (GainRaw, the camera's raw units), using 10"), std::string::npos)
      << warnings[0];
  EXPECT_EQ(warnings[0].find("dB"), std::string::npos) << "GainRaw has no unit: " << warnings[0];
  source.close();
}

TEST(CameraAravis, MissingCameraIsAClearNotFoundError)
{
  AravisSource source("sl_camera-no-such-camera", SourceSettings());
  try
  {
    source.open();
    FAIL() << "opening a camera that is not there must fail";
  }
  catch (const CameraError& e)
  {
    EXPECT_EQ(e.kind(), CameraError::Kind::NotFound);
    EXPECT_NE(std::string(e.what()).find("sl_camera-no-such-camera"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(source.isOpen());
}
