// The decoder in a running system: the cloud arrives in platform_edge with the wall where the scene
// puts it; the lazy ray ends, debug and depth outputs work; a missing transform publishes nothing.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <sl_testing/process.h>
#include <sl_testing/rostest_main.h>

TEST(DecoderNodelet, WallArrivesInPlatformEdge)
{
  ros::NodeHandle nh;
  const auto cloud = ros::topic::waitForMessage<sensor_msgs::PointCloud2>("points", nh, ros::Duration(120.0));
  ASSERT_TRUE(cloud) << "no points";
  EXPECT_EQ(cloud->header.frame_id, "platform_edge");
  ASSERT_GT(cloud->width * cloud->height, 600u);
  std::vector<std::string> names;
  for (const auto& f : cloud->fields)
    names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{ "x", "y", "z", "confidence", "row", "col", "u", "v", "sx", "sy", "sz" }));
  // sx, sy, sz: the projector centre in platform_edge (about 25 mm right of the camera's 25 mm left).
  sensor_msgs::PointCloud2ConstIterator<float> s(*cloud, "sx");
  EXPECT_NEAR(s[0], -0.030 + 0.01156, 0.01);
  EXPECT_NEAR(s[1], 0.025 - 0.05524, 0.01);
  EXPECT_NEAR(s[2], 0.0865 + 0.00398, 0.01);
  // plane_700: a wall perpendicular to the robot 700 mm in front of the camera, which sits 30 mm
  // behind the edge: x = 0.670 m in platform_edge, seen from the floor up, across the window.
  double sum_x = 0.0, min_z = 1e9, max_z = -1e9, min_y = 1e9, max_y = -1e9;
  size_t n = 0, off_wall = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(*cloud, "x"); it != it.end(); ++it)
  {
    sum_x += it[0];
    off_wall += std::abs(it[0] - 0.670) > 0.01;
    min_y = std::min(min_y, static_cast<double>(it[1]));
    max_y = std::max(max_y, static_cast<double>(it[1]));
    min_z = std::min(min_z, static_cast<double>(it[2]));
    max_z = std::max(max_z, static_cast<double>(it[2]));
    ++n;
  }
  EXPECT_NEAR(sum_x / n, 0.670, 0.003);
  EXPECT_EQ(off_wall, 0u);
  EXPECT_LT(min_z, 0.02);
  EXPECT_GT(max_z, 0.17);
  EXPECT_LT(min_y, -0.15);
  EXPECT_GT(max_y, 0.15);
}

TEST(DecoderNodelet, RayEndsOnDemand)
{
  ros::NodeHandle nh;
  const auto cloud = ros::topic::waitForMessage<sensor_msgs::PointCloud2>("ray_ends", nh, ros::Duration(60.0));
  ASSERT_TRUE(cloud) << "no ray_ends";
  EXPECT_EQ(cloud->header.frame_id, "platform_edge");
  std::vector<std::string> names;
  for (const auto& f : cloud->fields)
    names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{ "x", "y", "z", "sx", "sy", "sz", "state", "row", "col" }));
  // plane_700: about 840 of the 1024 primitives are decoded, the rest come here; no ray ends
  // beyond the wall (x = 0.670 m in platform_edge).
  EXPECT_GT(cloud->width, 100u);
  EXPECT_LT(cloud->width, 300u);
  size_t beyond = 0, decoded = 0;
  sensor_msgs::PointCloud2ConstIterator<uint8_t> state(*cloud, "state");
  for (sensor_msgs::PointCloud2ConstIterator<float> it(*cloud, "x"); it != it.end(); ++it, ++state)
  {
    decoded += *state == 0;
    beyond += std::isfinite(it[0]) && it[0] > 0.670 + 0.02;
  }
  EXPECT_EQ(decoded, 0u);
  EXPECT_EQ(beyond, 0u);
}

TEST(DecoderNodelet, DebugAndDepthImagesOnDemand)
{
  ros::NodeHandle nh;
  const auto debug = ros::topic::waitForMessage<sensor_msgs::Image>("debug_image", nh, ros::Duration(60.0));
  ASSERT_TRUE(debug);
  EXPECT_EQ(debug->encoding, "bgr8");
  EXPECT_EQ(debug->width, 752u);
  const auto depth = ros::topic::waitForMessage<sensor_msgs::Image>("depth/image_raw", nh, ros::Duration(60.0));
  ASSERT_TRUE(depth);
  EXPECT_EQ(depth->encoding, "32FC1");
  EXPECT_EQ(depth->header.frame_id, "camera_optical_frame");
  const float* z = reinterpret_cast<const float*>(depth->data.data());
  size_t valid = 0;
  for (size_t i = 0; i < depth->width * depth->height; ++i)
    if (std::isfinite(z[i]))
    {
      ++valid;
      EXPECT_NEAR(z[i], 0.70, 0.02);
    }
  EXPECT_GT(valid, 600u);
}

TEST(DecoderNodelet, MissingTransformPublishesNothing)
{
  ros::NodeHandle nh;
  std::atomic<int> good{ 0 }, bad{ 0 };
  ros::Subscriber ok =
      nh.subscribe<sensor_msgs::PointCloud2>("points", 5, [&](const sensor_msgs::PointCloud2ConstPtr&) { ++good; });
  ros::Subscriber no_tf = nh.subscribe<sensor_msgs::PointCloud2>(
      "no_tf/points", 5, [&](const sensor_msgs::PointCloud2ConstPtr&) { ++bad; });
  ros::Subscriber no_tf_rays = nh.subscribe<sensor_msgs::PointCloud2>(
      "no_tf/ray_ends", 5, [&](const sensor_msgs::PointCloud2ConstPtr&) { ++bad; });
  // Publishing nothing proves nothing unless the decoder without a transform was decoding all along:
  // its diagnostics count the frames it decoded, the points of the last one and the failed look-ups.
  std::mutex mutex;
  std::map<std::string, double> no_tf_diag;
  ros::Subscriber diagnostics =
      nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 20,
                                                     [&](const diagnostic_msgs::DiagnosticArrayConstPtr& msg)
                                                     {
                                                       for (const auto& status : msg->status)
                                                         if (status.name == "decoder_no_tf: decoding")
                                                         {
                                                           std::lock_guard<std::mutex> lock(mutex);
                                                           for (const auto& kv : status.values)
                                                             no_tf_diag[kv.key] = std::atof(kv.value.c_str());
                                                         }
                                                     });
  const auto diag = [&](const std::string& key)
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = no_tf_diag.find(key);
    return it == no_tf_diag.end() ? -1.0 : it->second;
  };
  ros::AsyncSpinner spinner(1);
  spinner.start();
  // Both decoders see the same images; wait until the one with a transform has published a few
  // clouds since both were subscribed, and the other has reported as many decoded frames.
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(60.0);
  while ((good < 6 || diag("frames") < 6) && ros::WallTime::now() < give_up)
    ros::WallDuration(0.05).sleep();
  EXPECT_GE(good.load(), 6) << "the decoder with a transform published too little";
  EXPECT_EQ(bad.load(), 0) << "points or ray ends published without a transform to their frame";
  // It decoded the wall (about 840 points a frame, as the other decoder) and then found no transform
  // for every frame (the count is read apart from the frames, so it may trail by one).
  const double frames = diag("frames");
  EXPECT_GE(frames, 6.0) << "the decoder without a transform decoded too little (-1: no diagnostics)";
  EXPECT_GT(diag("valid points"), 600.0) << "the decoder without a transform found no wall";
  EXPECT_GE(diag("tf failures"), frames - 1.0) << "frames decoded but no failed look-up counted";
  EXPECT_GT(diag("tf failures"), 0.0);
}

TEST(DecoderNode, BadParameterExitsNamingIt)
{
  struct Case
  {
    std::string args, expected;
  };
  const std::string rig = " _calibration_file:=$(rospack find sl_projector)/config/default_rig.yaml";
  const std::vector<Case> cases = {
    { "_calibration_file:=/no/such_rig.yaml", "~calibration_file: /no/such_rig.yaml: cannot open" },
    { "_tf_timeout:=9" + rig, "~tf_timeout must be in [0, 5] s" },
    { "_queue_size:=many" + rig, "~queue_size must be an integer" },
  };
  int k = 0;
  for (const Case& c : cases)
  {
    std::string out;
    const int status = sl_testing::run(
        "timeout 90 rosrun sl_decoder decoder_node __name:=bad_decoder" + std::to_string(k++) + " " + c.args, out);
    EXPECT_NE(status, 0) << c.args << "\n" << out;
    EXPECT_NE(status, 124) << "the node did not exit: " << c.args << "\n" << out;
    EXPECT_NE(out.find(c.expected), std::string::npos) << c.args << "\n" << out;
  }
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "decoder_rostest", 0);
}
