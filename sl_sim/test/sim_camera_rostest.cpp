// The sim_camera nodelet in a running system (see sim_camera.test): projector and simulated camera
// in one manager; images with camera_info from the rig, depth, contact, collision, the pose from tf, and
// parameters that stop the node with a message naming them. sim_camera_clock.test runs this binary
// on a simulated clock that the test drives: one image per period of the set rate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <sl_msgs/Collision.h>
#include <sl_testing/process.h>
#include <sl_testing/rostest_main.h>
#include <sl_testing/wait.h>
#include <std_msgs/UInt8.h>

using sl_testing::run;
using sl_testing::waitForMessage;

namespace
{
float centreDepth(const sensor_msgs::Image& depth)
{
  const size_t offset = (static_cast<size_t>(depth.height / 2) * depth.width + depth.width / 2) * sizeof(float);
  float z;
  std::memcpy(&z, depth.data.data() + offset, sizeof z);
  return z;
}

// Depth (camera z) of pixel (372, 243), the principal point, on a plane 0.700 m ahead of the
// camera along the robot's x axis (the camera is yawed by atan(25 / 675)).
const double kYaw = 0.03702;
}  // namespace

TEST(SimCamera, ImagesArriveWithCameraInfoFromTheRig)
{
  ros::NodeHandle nh;
  std::mutex mutex;
  std::vector<sensor_msgs::ImageConstPtr> images;
  std::vector<sensor_msgs::CameraInfoConstPtr> infos;
  ros::Subscriber image_sub = nh.subscribe<sensor_msgs::Image>("/camera/image_raw", 10,
                                                               [&](const sensor_msgs::ImageConstPtr& m)
                                                               {
                                                                 std::lock_guard<std::mutex> lock(mutex);
                                                                 images.push_back(m);
                                                               });
  ros::Subscriber info_sub = nh.subscribe<sensor_msgs::CameraInfo>("/camera/camera_info", 10,
                                                                   [&](const sensor_msgs::CameraInfoConstPtr& m)
                                                                   {
                                                                     std::lock_guard<std::mutex> lock(mutex);
                                                                     infos.push_back(m);
                                                                   });
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // The first image comes once the projector's (latched) pattern has arrived; the rate itself is
  // checked on a simulated clock (SimCameraClock below).
  ASSERT_TRUE(sl_testing::waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(mutex);
        return images.size() >= 3;
      },
      60.0, 0.05))
      << "fewer than 3 images on /camera/image_raw";

  std::lock_guard<std::mutex> lock(mutex);
  const sensor_msgs::Image& image = *images.back();
  EXPECT_EQ(image.encoding, sensor_msgs::image_encodings::MONO8);
  EXPECT_EQ(image.width, 752u);
  EXPECT_EQ(image.height, 480u);
  EXPECT_EQ(image.step, 752u);
  ASSERT_EQ(image.data.size(), 752u * 480u);
  EXPECT_EQ(image.header.frame_id, "camera_optical_frame");
  // The pattern is visible: bright blobs on a dark background.
  size_t bright = 0;
  for (uint8_t v : image.data)
    bright += v > 120;
  EXPECT_GT(bright, image.data.size() / 10);
  EXPECT_LT(bright, image.data.size() / 2);

  ASSERT_FALSE(infos.empty());
  const sensor_msgs::CameraInfo& info = *infos.back();
  EXPECT_EQ(info.width, 752u);
  EXPECT_EQ(info.height, 480u);
  EXPECT_EQ(info.header.frame_id, "camera_optical_frame");
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_DOUBLE_EQ(info.K[0], 1492.0);
  EXPECT_DOUBLE_EQ(info.K[2], 372.0);
  EXPECT_DOUBLE_EQ(info.K[4], 1492.0);
  EXPECT_DOUBLE_EQ(info.K[5], 243.0);
  EXPECT_DOUBLE_EQ(info.K[8], 1.0);
  ASSERT_EQ(info.D.size(), 5u);
  EXPECT_DOUBLE_EQ(info.D[0], -0.08);
  EXPECT_DOUBLE_EQ(info.D[1], 0.12);
  EXPECT_DOUBLE_EQ(info.P[0], 1492.0);
  EXPECT_DOUBLE_EQ(info.P[10], 1.0);
  // Image and camera_info of a frame share the stamp (checked on the frame before the last: the
  // last image's camera_info may still be on its way when collection stops).
  ASSERT_GE(images.size(), 2u);
  bool matched = false;
  for (const auto& i : infos)
    matched |= i->header.stamp == images[images.size() - 2]->header.stamp;
  EXPECT_TRUE(matched);
  // Successive images differ (noise), and their stamps increase.
  ASSERT_GE(images.size(), 2u);
  EXPECT_NE(images[images.size() - 2]->data, image.data);
  EXPECT_LT(images[images.size() - 2]->header.stamp, image.header.stamp);
}

// sim_camera_clock.test: /use_sim_time, and this test is the only /clock. The clock moves in steps
// of a quarter period and stands still until the image of a step has come (or, for a step where none
// is due, a short while): an image's stamp is then exactly the clock value at which it was rendered,
// so the stamps show whether the camera renders once per period of ROS time, with no wall time measured.
TEST(SimCameraClock, OneImagePerPeriodOfTheSimulatedClock)
{
  ros::NodeHandle nh;
  bool sim_time = false;
  ASSERT_TRUE(ros::param::get("/use_sim_time", sim_time) && sim_time) << "run by sim_camera_clock.test";
  std::mutex mutex;
  std::vector<ros::Time> stamps;
  ros::Subscriber image_sub = nh.subscribe<sensor_msgs::Image>("/camera/image_raw", 10,
                                                               [&](const sensor_msgs::ImageConstPtr& m)
                                                               {
                                                                 std::lock_guard<std::mutex> lock(mutex);
                                                                 stamps.push_back(m->header.stamp);
                                                               });
  ros::Publisher clock_pub = nh.advertise<rosgraph_msgs::Clock>("/clock", 1);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const double rate = 5.0;  // sim_camera_clock.test
  const ros::Duration period(1.0 / rate);
  const ros::Duration step(0, period.nsec / 4);  // 50 ms: exact in nanoseconds
  const ros::Time start(100, 0);
  rosgraph_msgs::Clock clock;
  clock.clock = start;
  // Hold the clock at the start until the camera is up. Its timer then runs on the grid of our steps:
  // created at the start (first image one period later), or created at time 0 and restarted by the
  // jump to the start, where roscpp may fire it twice. Images stamped at the start are left out.
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(120.0);
  while (ros::ok() && image_sub.getNumPublishers() == 0 && ros::WallTime::now() < give_up)
  {
    clock_pub.publish(clock);
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_GT(image_sub.getNumPublishers(), 0u) << "no /camera/image_raw publisher";
  for (int i = 0; i < 20; ++i)  // the new subscription's connection, the held clock reaching the camera
  {
    clock_pub.publish(clock);
    ros::WallDuration(0.05).sleep();
  }
  const auto count = [&]
  {
    std::lock_guard<std::mutex> lock(mutex);
    return std::count_if(stamps.begin(), stamps.end(), [&](const ros::Time& t) { return t > start; });
  };
  const auto last = [&]
  {
    std::lock_guard<std::mutex> lock(mutex);
    return stamps.empty() ? ros::Time() : stamps.back();
  };
  size_t steps = 0;
  ros::Time due;  // one period after the last image
  while (ros::ok() && count() < 17 && ros::WallTime::now() < give_up)
  {
    clock.clock += step;
    ++steps;
    const auto before = count();
    clock_pub.publish(clock);
    // Wait for this step's image: at a step where one is due, as long as it takes (up to the give-up:
    // a loaded machine only delays it, and the clock waits); at the others a while, to see an image
    // that should not come (rendering takes about 10 ms).
    const bool is_due = !due.isZero() && clock.clock >= due;
    const ros::WallTime wait_end = std::min(give_up, ros::WallTime::now() + ros::WallDuration(is_due ? 30.0 : 0.2));
    while (count() == before && ros::WallTime::now() < wait_end)
      ros::WallDuration(0.002).sleep();
    if (count() != before)
      due = last() + period;
  }
  std::lock_guard<std::mutex> lock(mutex);
  stamps.erase(std::remove_if(stamps.begin(), stamps.end(), [&](const ros::Time& t) { return t <= start; }),
               stamps.end());
  ASSERT_GE(stamps.size(), 17u) << "only " << stamps.size() << " images in " << steps << " clock steps";
  // From the first image on (before it the pattern may not have arrived): stamps are clock values
  // we published, one per period, none skipped, none doubled.
  std::vector<double> intervals;
  for (size_t i = 0; i < stamps.size(); ++i)
  {
    EXPECT_EQ((stamps[i] - start).toNSec() % step.toNSec(), 0) << "a stamp between two clock steps";
    if (i == 0)
      continue;
    intervals.push_back((stamps[i] - stamps[i - 1]).toSec());
    // Never two in a period. (Only the first image may come a step late, when the machine stalls
    // for 0.2 s before any is due; the second then comes a step early.)
    EXPECT_GE(intervals.back(), (period - step).toSec() - 1e-9) << "two images within one period";
  }
  std::vector<double> sorted = intervals;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  EXPECT_NEAR(sorted[sorted.size() / 2], period.toSec(), 1e-6) << "median interval of the stamps";
  const int periods = static_cast<int>(std::lround((stamps.back() - stamps.front()).toSec() / period.toSec()));
  EXPECT_EQ(periods, static_cast<int>(stamps.size()) - 1) << "images skipped or doubled";
}

TEST(SimCamera, GroundTruthDepthAndContact)
{
  const auto depth = waitForMessage<sensor_msgs::Image>("/camera/depth/image_raw", 60.0);
  ASSERT_TRUE(depth) << "no depth image";
  EXPECT_EQ(depth->encoding, sensor_msgs::image_encodings::TYPE_32FC1);
  EXPECT_EQ(depth->width, 752u);
  EXPECT_EQ(depth->height, 480u);
  EXPECT_EQ(depth->step, 752u * 4u);
  EXPECT_EQ(depth->header.frame_id, "camera_optical_frame");
  EXPECT_NEAR(centreDepth(*depth), 0.700 / std::cos(kYaw), 2e-3);
  const auto depth_info = waitForMessage<sensor_msgs::CameraInfo>("/camera/depth/camera_info", 30.0);
  ASSERT_TRUE(depth_info);
  EXPECT_DOUBLE_EQ(depth_info->K[0], 1492.0);

  // Contact is published even when nobody asks for images; the plane is far from the bumper.
  const auto contact = waitForMessage<std_msgs::UInt8>("/camera/contact", 30.0);
  ASSERT_TRUE(contact) << "no contact message";
  EXPECT_EQ(contact->data, 0);
}

TEST(SimCamera, CollisionGroundTruth)
{
  // The default pose: the disc's front edge at the world origin, 0.670 m before the plane.
  const auto collision = waitForMessage<sl_msgs::Collision>("/camera/collision", 30.0);
  ASSERT_TRUE(collision) << "no collision message";
  EXPECT_FALSE(collision->colliding);
  EXPECT_TRUE(collision->objects.empty());
  EXPECT_NEAR(collision->min_clearance, 0.670, 1e-9);
  EXPECT_EQ(collision->nearest_object, "plane");
  EXPECT_EQ(collision->header.frame_id, "world");
  EXPECT_FALSE(collision->header.stamp.isZero());
  // camera_tf: from tf, 100 mm nearer (the default pose until the static transforms arrive).
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(30.0);
  double clearance = 0.0;
  while (ros::WallTime::now() < give_up)
  {
    const auto msg = waitForMessage<sl_msgs::Collision>("/camera_tf/collision", 30.0);
    ASSERT_TRUE(msg) << "no collision message from camera_tf";
    clearance = msg->min_clearance;
    if (std::abs(clearance - 0.570) < 1e-6)
      break;
  }
  EXPECT_NEAR(clearance, 0.570, 1e-6);
}

TEST(SimCamera, PoseComesFromTf)
{
  // camera_tf: tf puts the robot 100 mm further forward, so the plane is 600 mm from the camera.
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(60.0);
  double z = 0.0;
  while (ros::WallTime::now() < give_up)
  {
    const auto depth = waitForMessage<sensor_msgs::Image>("/camera_tf/depth/image_raw", 30.0);
    ASSERT_TRUE(depth) << "no depth image from camera_tf";
    z = centreDepth(*depth);
    // Until the static transforms have arrived the nodelet uses the default pose (700 mm).
    if (std::abs(z - 0.600 / std::cos(kYaw)) < 2e-3)
      break;
  }
  EXPECT_NEAR(z, 0.600 / std::cos(kYaw), 2e-3);
}

TEST(SimCameraNode, InvalidParametersFailNamingThem)
{
  const std::string rig = std::string(SL_PROJECTOR_CONFIG_DIR) + "/default_rig.yaml";
  const std::string scene = std::string(SL_SIM_SCENES_DIR) + "/plane_700.yaml";
  struct Case
  {
    std::string args;
    std::string expected;
  };
  const std::vector<Case> cases = {
    { "_scene_file:=" + scene, "~calibration_file: required" },
    { "_calibration_file:=/no/such/rig.yaml _scene_file:=" + scene,
      "~calibration_file: /no/such/rig.yaml: cannot open" },
    { "_rig_file:=/no/such/rig.yaml _scene_file:=" + scene, "~calibration_file: /no/such/rig.yaml: cannot open" },
    { "_calibration_file:=" + rig, "~scene_file: required" },
    { "_calibration_file:=" + rig + " _scene_file:=/no/such/scene.yaml",
      "~scene_file: /no/such/scene.yaml: cannot open" },
    { "_rig_file:=" + rig + " _scene_file:=/no/such/scene.yaml", "~rig_file is deprecated: use ~calibration_file" },
    { "_calibration_file:=" + rig + " _scene_file:=" + scene + " _antialias:=3", "~antialias: must be 1, 4 or 16" },
    { "_calibration_file:=" + rig + " _scene_file:=" + scene + " _rate:=0.0", "~rate" },
    { "_calibration_file:=" + rig + " _scene_file:=" + scene + " _collision_rate:=-1.0", "~collision_rate" },
    { "_calibration_file:=" + rig + " _scene_file:=" + scene + " _robot_radius:=-1.0", "~robot_radius" },
  };
  int k = 0;
  for (const Case& c : cases)
  {
    std::string out;
    const int status =
        run("rosrun sl_sim sim_camera_node __name:=bad_sim_camera_" + std::to_string(k++) + " " + c.args +
                " image_raw:=bad_image pattern:=bad_pattern contact:=bad_contact collision:=bad_collision",
            out);
    EXPECT_NE(status, 0) << c.args << "\n" << out;
    EXPECT_NE(out.find(c.expected), std::string::npos) << c.args << "\n" << out;
  }
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "sim_camera_rostest", 0);
}
