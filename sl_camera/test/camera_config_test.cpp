// CameraConfig: validation names the parameter; the factory builds the right source.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include <sl_testing/errors.h>
#include "sl_camera/camera/camera_config.h"

using sl_camera::CameraBackend;
using sl_camera::CameraConfig;

using sl_testing::validationError;

namespace
{
bool startsWith(const std::string& s, const std::string& prefix)
{
  return s.rfind(prefix, 0) == 0;
}
}  // namespace

TEST(CameraConfig, BackendNames)
{
  EXPECT_EQ(sl_camera::parseCameraBackend("v4l2"), CameraBackend::V4l2);
  EXPECT_EQ(sl_camera::parseCameraBackend("aravis"), CameraBackend::Aravis);
  EXPECT_EQ(sl_camera::parseCameraBackend("player"), CameraBackend::Player);
  try
  {
    sl_camera::parseCameraBackend("usb");
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_TRUE(startsWith(e.what(), "backend must be one of v4l2, aravis, player")) << e.what();
  }
  EXPECT_TRUE(sl_camera::cameraBackendAvailable(CameraBackend::V4l2));
  EXPECT_TRUE(sl_camera::cameraBackendAvailable(CameraBackend::Player));
}

TEST(CameraConfig, DefaultsAreValid)
{
  CameraConfig c;
  EXPECT_EQ(validationError(c), "");
  EXPECT_EQ(c.resolvedDevice(), "/dev/video0");
}

TEST(CameraConfig, InvalidValuesNameTheParameter)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case
  {
    std::function<void(CameraConfig&)> change;
    const char* name;
  } cases[] = {
    { [](CameraConfig& c) { c.settings.rate = 0.0; }, "rate must be > 0" },
    { [](CameraConfig& c) { c.settings.rate = -1.0; }, "rate must be > 0" },
    { [nan](CameraConfig& c) { c.settings.rate = nan; }, "rate must be > 0" },
    { [](CameraConfig& c) { c.settings.width = -2; }, "width " },
    { [](CameraConfig& c) { c.settings.height = 70000; }, "height " },
    { [nan](CameraConfig& c) { c.settings.exposure = nan; }, "exposure " },
    { [](CameraConfig& c) { c.settings.exposure = 60.0; }, "exposure " },
    { [](CameraConfig& c) { c.settings.gain = std::numeric_limits<double>::infinity(); }, "gain " },
    { [](CameraConfig& c) { c.reconnect_max_backoff = 0.0; }, "reconnect_max_backoff " },
    { [](CameraConfig& c) { c.backend = CameraBackend::Player; }, "device " },
    { [](CameraConfig& c) { c.settings.offset_x = -2; }, "offset_x " },
    { [](CameraConfig& c) { c.settings.offset_y = 70000; }, "offset_y " },
    { [](CameraConfig& c) { c.stall_timeout = 0.0; }, "stall_timeout " },
    { [nan](CameraConfig& c) { c.stall_timeout = nan; }, "stall_timeout " },
    { [](CameraConfig& c) { c.aravis.socket_buffer = 1000; }, "socket_buffer " },
    { [](CameraConfig& c) { c.aravis.socket_buffer = -1; }, "socket_buffer " },
    { [](CameraConfig& c) { c.aravis.packet_size = 100; }, "packet_size " },
    { [](CameraConfig& c) { c.aravis.packet_size = 70000; }, "packet_size " },
  };
  for (const Case& k : cases)
  {
    CameraConfig c;
    k.change(c);
    const std::string error = validationError(c);
    EXPECT_TRUE(startsWith(error, k.name)) << "expected '" << k.name << "...', got '" << error << "'";
  }
}

TEST(CameraConfig, CaptureOptionsFollowTheSettings)
{
  CameraConfig c;
  c.reconnect_max_backoff = 2.0;
  c.settings.rate = 0.5;  // one frame every 2 s
  const sl_camera::CaptureOptions o = c.captureOptions();
  EXPECT_NO_THROW(o.validate());
  EXPECT_DOUBLE_EQ(o.max_backoff, 2.0);
  EXPECT_LE(o.initial_backoff, o.max_backoff);
  EXPECT_GE(o.stall_timeout, 3.0 / 0.5) << "slow sources must not look stalled";
  c.reconnect_max_backoff = 0.1;
  EXPECT_LE(c.captureOptions().initial_backoff, 0.1);
}

TEST(CameraConfig, StallTimeoutIsOneSecondByDefaultAndOverdueComesFirst)
{
  CameraConfig c;
  c.settings.rate = 10.0;
  const sl_camera::CaptureOptions o = c.captureOptions();
  EXPECT_NO_THROW(o.validate());
  EXPECT_DOUBLE_EQ(o.stall_timeout, 1.0);
  EXPECT_GE(o.first_frame_timeout, o.stall_timeout);
  EXPECT_LT(o.frame_overdue, o.stall_timeout);
  c.stall_timeout = 0.2;
  EXPECT_DOUBLE_EQ(c.captureOptions().stall_timeout, 0.3) << "three frame periods at 10 Hz";
}

TEST(CameraConfig, PacketSocketModes)
{
  EXPECT_EQ(sl_camera::parsePacketSocketMode("auto"), sl_camera::PacketSocketMode::Auto);
  EXPECT_EQ(sl_camera::parsePacketSocketMode("off"), sl_camera::PacketSocketMode::Off);
  try
  {
    sl_camera::parsePacketSocketMode("on");
    FAIL() << "only auto and off";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_TRUE(startsWith(e.what(), "packet_socket ")) << e.what();
  }
}

TEST(CameraConfig, RigSizeIsTakenOrMustMatch)
{
  CameraConfig c;
  c.applyRigSize(752, 480, "/tmp/rig.yaml");
  EXPECT_EQ(c.settings.width, 752);
  EXPECT_EQ(c.settings.height, 480);
  c.applyRigSize(752, 480, "/tmp/rig.yaml");  // the same size again is fine

  CameraConfig other;
  other.settings.width = 1280;
  other.settings.height = 1024;
  try
  {
    other.applyRigSize(752, 480, "/tmp/rig.yaml");
    FAIL() << "a size that differs from the rig's must be refused";
  }
  catch (const std::invalid_argument& e)
  {
    const std::string m = e.what();
    EXPECT_TRUE(startsWith(m, "width")) << m;
    EXPECT_NE(m.find("1280 x 1024"), std::string::npos) << m;
    EXPECT_NE(m.find("752 x 480"), std::string::npos) << m;
    EXPECT_NE(m.find("/tmp/rig.yaml"), std::string::npos) << m;
  }
  CameraConfig half;
  half.settings.width = 752;  // height left at 0: not the rig's size either
  EXPECT_THROW(half.applyRigSize(752, 480, "/tmp/rig.yaml"), std::invalid_argument);
}

TEST(CameraConfig, FactoryBuildsTheBackend)
{
  CameraConfig c;
  c.device = "3";
  EXPECT_EQ(sl_camera::createFrameSource(c)->description(), "V4L2 device /dev/video3");
  c.backend = CameraBackend::Player;
  c.device = "/data/run1";
  EXPECT_EQ(sl_camera::createFrameSource(c)->description(), "player of /data/run1");
  c.backend = CameraBackend::Aravis;
  c.device = "";
  if (sl_camera::cameraBackendAvailable(CameraBackend::Aravis))
  {
    EXPECT_EQ(sl_camera::createFrameSource(c)->description(), "Aravis camera (first found)");
  }
  else
  {
    EXPECT_THROW(sl_camera::createFrameSource(c), std::invalid_argument);
    EXPECT_TRUE(startsWith(validationError(c), "backend aravis is not available"));
  }
}
