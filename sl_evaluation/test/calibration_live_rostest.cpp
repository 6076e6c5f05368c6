// The live calibration nodelet in a running simulation: the plane procedure end to end (prompted
// distances, captures through the service, the file written after the last one), and the full
// procedure's errors on images without a board.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <std_msgs/Float64.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>

#include "sl_rig/rig.h"

namespace
{
std::string param(const std::string& name)
{
  std::string value;
  EXPECT_TRUE(ros::param::get("~" + name, value)) << name;
  return value;
}

bool call(const std::string& service, std_srvs::Trigger::Response& res)
{
  if (!ros::service::waitForService(service, ros::Duration(60.0)))
    return false;
  std_srvs::Trigger srv;
  const bool ok = ros::service::call(service, srv);
  res = srv.response;
  return ok;
}

std::vector<std::string> split(const std::string& line)
{
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string item;
  while (std::getline(s, item, ','))
    out.push_back(item);
  if (!line.empty() && line.back() == ',')
    out.push_back("");
  return out;
}
}  // namespace

TEST(CalibrationLive, PlaneProcedureInSimulation)
{
  const std::string output = param("plane_output");
  const std::string residuals = param("plane_residuals");
  std::remove(output.c_str());
  ros::NodeHandle nh;
  // The first prompt names the first distance, for the user and for the stage.
  const auto first =
      ros::topic::waitForMessage<std_msgs::Float64>("/calibration/next_distance", nh, ros::Duration(60.0));
  ASSERT_TRUE(first);
  EXPECT_NEAR(first->data, 0.5, 1e-9);
  const auto prompt = ros::topic::waitForMessage<std_msgs::String>("/calibration/status", nh, ros::Duration(10.0));
  ASSERT_TRUE(prompt);
  EXPECT_NE(prompt->data.find("put the plane at 0.500 m"), std::string::npos) << prompt->data;

  std_srvs::Trigger::Response res;
  for (const std::string d : { "0.500", "0.700", "0.900" })
  {
    ros::Duration(0.5).sleep();  // the stage moves the robot on the prompt
    ASSERT_TRUE(call("/calibration/capture", res));
    EXPECT_TRUE(res.success) << res.message;
    EXPECT_EQ(res.message.rfind(d + " m: ", 0), 0u) << res.message;
  }
  // After the last listed distance the calibration ran and wrote the file.
  EXPECT_NE(res.message.find("wrote " + output), std::string::npos) << res.message;
  const sl_projector::Rig rig = sl_projector::loadRig(output);
  ASSERT_EQ(rig.tables.rational.size(), 1024u);
  ASSERT_EQ(rig.tables.linear.size(), 1024u);
  int valid = 0;
  for (const sl_projector::DepthModel& m : rig.tables.rational)
    valid += m.valid;
  EXPECT_GT(valid, 600);
  EXPECT_EQ(rig.tables.distances, (std::vector<double>{ 0.5, 0.7, 0.9 }));

  // The wall really was at three distances: each calibrated primitive moved along its row in the
  // image by tens of pixels, and the models give the plane's depth there.
  std::ifstream csv(residuals);
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  int checked = 0;
  while (std::getline(csv, line))
  {
    const std::vector<std::string> f = split(line);
    if (f.size() < 13 || f[3] != "calibrated")
      continue;
    const double u500 = std::stod(f[4]), u900 = std::stod(f[10]);
    EXPECT_GT(u500 - u900, 30.0) << line;  // the pattern moves left as the depth grows
    const sl_projector::DepthModel& m =
        rig.tables.rational[static_cast<size_t>(std::stoi(f[0]) * 64 + std::stoi(f[1]))];
    EXPECT_GT(m.depth(u500), 0.49);
    EXPECT_LT(m.depth(u900), 0.95);
    ++checked;
  }
  EXPECT_GT(checked, 600);

  // Nothing more to capture without a new distance.
  ASSERT_TRUE(call("/calibration/capture", res));
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("no distance"), std::string::npos) << res.message;
  std::remove(output.c_str());
  std::remove(residuals.c_str());
}

TEST(CalibrationLive, FullProcedureErrors)
{
  const std::string output = param("full_output");
  std::remove(output.c_str());
  std_srvs::Trigger::Response res;
  // The wall has no checkerboard.
  ASSERT_TRUE(call("/calibration_full/capture_board", res));
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("checkerboard of 9x6 inner corners not found"), std::string::npos) << res.message;
  ASSERT_TRUE(call("/calibration_full/capture_pattern", res));
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("capture the board image of this pose first"), std::string::npos) << res.message;
  ASSERT_TRUE(call("/calibration_full/calibrate", res));
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("nothing written"), std::string::npos) << res.message;
  EXPECT_NE(res.message.find("needs >= 3 plane poses"), std::string::npos) << res.message;
  std::ifstream f(output);
  EXPECT_FALSE(f.good()) << output << " was written";
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "calibration_live_rostest");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
