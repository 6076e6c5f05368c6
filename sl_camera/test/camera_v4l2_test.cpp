// V4l2Source without hardware: a device that is not there is a clear error, not a crash.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "sl_camera/camera/v4l2_source.h"

using sl_camera::CameraError;
using sl_camera::SourceSettings;
using sl_camera::V4l2Source;

TEST(CameraV4l2, DevicePathFromIndexOrPath)
{
  EXPECT_EQ(V4l2Source::devicePath("0"), "/dev/video0");
  EXPECT_EQ(V4l2Source::devicePath("12"), "/dev/video12");
  EXPECT_EQ(V4l2Source::devicePath("/dev/v4l/by-id/usb-cam"), "/dev/v4l/by-id/usb-cam");
}

TEST(CameraV4l2, MissingDeviceIsAClearNotFoundError)
{
  for (const std::string device : { "/dev/sl_camera_no_such_video", "987" })
  {
    V4l2Source source(device, SourceSettings());
    EXPECT_EQ(source.description(), "V4L2 device " + V4l2Source::devicePath(device));
    try
    {
      source.open();
      FAIL() << "opening " << device << " must fail";
    }
    catch (const CameraError& e)
    {
      EXPECT_EQ(e.kind(), CameraError::Kind::NotFound);
      EXPECT_NE(std::string(e.what()).find(V4l2Source::devicePath(device)), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(source.isOpen());
    sl_camera::Frame frame;
    EXPECT_THROW(source.grab(frame, std::chrono::milliseconds(10)), CameraError);
    source.close();  // harmless when not open
  }
}

TEST(CameraV4l2, SomethingThatIsNotADeviceIsRefused)
{
  V4l2Source source("/etc/hostname", SourceSettings());
  try
  {
    source.open();
    FAIL() << "a regular file is not a camera";
  }
  catch (const CameraError& e)
  {
    EXPECT_EQ(e.kind(), CameraError::Kind::Open);
    EXPECT_NE(std::string(e.what()).find("/etc/hostname"), std::string::npos) << e.what();
  }
}
