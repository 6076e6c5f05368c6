// Checks the projector nodelet in a running system: latched pattern and camera_info, and that bad
// parameters stop the node with a message naming the parameter. Also the nodelets' rig file
// parameter (sl_rig/ros/rig_param.h) against the parameter server.
#include <gtest/gtest.h>

#include <string>

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sl_testing/child_process.h>
#include <sl_testing/process.h>
#include <sl_testing/rostest_main.h>
#include <sl_testing/errors.h>
#include <sl_testing/wait.h>

#include "sl_rig/ros/rig_param.h"

using sl_testing::Child;
using sl_testing::run;
using sl_testing::waitForMessage;

TEST(ProjectorNodelet, PublishesLatchedPatternAndCameraInfo)
{
  // Subscribing late still gets the (latched) messages.
  const auto image = waitForMessage<sensor_msgs::Image>("pattern", 60.0);
  ASSERT_TRUE(image) << "no pattern";
  EXPECT_EQ(image->encoding, "mono8");
  EXPECT_EQ(image->width, 480u);
  EXPECT_EQ(image->height, 320u);
  EXPECT_EQ(image->step, 480u);
  EXPECT_EQ(image->data.size(), 480u * 320u);
  EXPECT_EQ(image->header.frame_id, "projector_optical_frame");
  size_t lit = 0;
  for (uint8_t v : image->data)
    lit += v == 255;
  EXPECT_EQ(lit, 16u * 64u * 33u);

  const auto info = waitForMessage<sensor_msgs::CameraInfo>("camera_info", 30.0);
  ASSERT_TRUE(info) << "no camera_info";
  EXPECT_EQ(info->width, 480u);
  EXPECT_EQ(info->height, 320u);
  // From the default rig file (see projector.test).
  EXPECT_DOUBLE_EQ(info->K[0], 753.0);
  EXPECT_DOUBLE_EQ(info->K[4], 781.0);
  EXPECT_DOUBLE_EQ(info->K[2], 203.0);
  EXPECT_DOUBLE_EQ(info->K[5], -38.0);
  ASSERT_EQ(info->D.size(), 5u);
  EXPECT_DOUBLE_EQ(info->D[0], 0.02);
  EXPECT_EQ(info->header.frame_id, "projector_optical_frame");
}

TEST(ProjectorNode, InvalidParameterFailsNamingIt)
{
  std::string out;
  const int status = run("rosrun sl_projector projector_node __name:=bad_projector _columns:=100", out);
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(out.find("~columns"), std::string::npos) << out;

  out.clear();
  const int status3 =
      run("rosrun sl_projector projector_node __name:=bad_projector3 _calibration_file:=/no/such.yaml", out);
  EXPECT_NE(status3, 0) << out;
  EXPECT_NE(out.find("~calibration_file: /no/such.yaml: cannot open"), std::string::npos) << out;

  out.clear();
  const int status2 = run("rosrun sl_projector projector_node __name:=bad_projector2 _fx:=-3.0", out);
  EXPECT_NE(status2, 0) << out;
  EXPECT_NE(out.find("~fx"), std::string::npos) << out;
}

TEST(ProjectorNode, MissingDisplayAndBusAreReportedNotFatal)
{
  // The node reports both and carries on: after the reports its (latched) pattern still comes and it
  // is still running until it is told to stop. Nothing here depends on how long it ran.
  Child node({ "rosrun", "sl_projector", "projector_node", "__name:=no_display_projector", "_show_window:=true",
               "_display:=unix:87", "_dlp_setup:=true", "_i2c_bus:=/dev/i2c-none", "pattern:=pattern_no_display",
               "camera_info:=info_no_display" });
  ASSERT_TRUE(node.readUntil({ "cannot open X display 'unix:87'", "/dev/i2c-none" }, 60.0)) << node.output();
  EXPECT_TRUE(waitForMessage<sensor_msgs::Image>("pattern_no_display", 60.0)) << "no pattern after the reports";
  EXPECT_TRUE(node.running()) << node.output();
  EXPECT_EQ(node.interrupt(), 0) << "exit status after SIGINT\n" << node.output();
}

TEST(RigParam, LoadsTheRigOrRefusesNamingTheParameter)
{
  using sl_projector::loadRigParam;
  using sl_testing::invalidArgumentOf;
  const std::string rig_file = SL_PROJECTOR_CONFIG_DIR "/default_rig.yaml";
  ros::NodeHandle good("~rig_good"), missing("~rig_missing"), number("~rig_number"), no_file("~rig_no_file"),
      old("~rig_old");
  good.setParam("calibration_file", rig_file);
  number.setParam("calibration_file", 3);
  no_file.setParam("calibration_file", "/no/such.yaml");
  old.setParam("rig_file", rig_file);

  const sl_projector::RigParam p = loadRigParam(good);
  EXPECT_EQ(p.file, rig_file);
  EXPECT_EQ(p.rig.camera.width, sl_projector::loadRig(rig_file).camera.width);
  EXPECT_EQ(invalidArgumentOf([&] { loadRigParam(missing); }).rfind("~calibration_file: required", 0), 0U);
  EXPECT_EQ(invalidArgumentOf([&] { loadRigParam(number); }), "~calibration_file must be a string, got an integer");
  EXPECT_EQ(invalidArgumentOf([&] { loadRigParam(no_file); }).rfind("~calibration_file: /no/such.yaml: cannot open", 0),
            0U);
  // The deprecated former name counts only where the nodelet still reads it.
  EXPECT_EQ(loadRigParam(old, "rig_file").file, rig_file);
  EXPECT_EQ(invalidArgumentOf([&] { loadRigParam(old); }).rfind("~calibration_file: required", 0), 0U);
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "projector_rostest", 0);
}
