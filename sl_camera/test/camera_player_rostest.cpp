// Checks the camera nodelet (player back-end) in a running system: the missing folder is reported
// and retried; once the PNGs are there they arrive in order, paired with a valid camera_info in the
// configured frame; a player waits for its first subscriber, who gets frame 0; unreadable files are
// named in the diagnostics; invalid parameters (and a size other than the rig's) stop the node
// naming the parameter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <image_transport/image_transport.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sl_testing/process.h>
#include <sl_testing/wait.h>

namespace fs = std::filesystem;
using sl_testing::run;
using sl_testing::waitUntil;

namespace
{
constexpr int kImages = 5;
constexpr int kWidth = 64;
constexpr int kHeight = 48;

std::string g_folder;
std::string g_early_folder;
std::string g_rig_file;

/// Grey value of image i (0-based): 40, 80, ..., 200.
int valueOf(int i)
{
  return 40 * (i + 1);
}

/// Files in the early folder that no image decoder can read, sorted between the frames.
const std::vector<std::string> kUnreadable = { "frame_001b.png", "frame_003b.png" };

/// Writes the images (and, if @p with_unreadable, the files of kUnreadable) into a staging folder
/// and renames it to @p folder, so a camera never sees a half-written folder. Idempotent.
void ensureFolder(const std::string& folder = g_folder, bool with_unreadable = false)
{
  if (fs::exists(folder))
    return;
  const std::string staging = folder + ".staging";
  fs::create_directories(staging);
  if (with_unreadable)
  {
    std::ofstream(fs::path(staging) / kUnreadable[0], std::ios::binary) << "\x89PNG not really a PNG";
    std::ofstream(fs::path(staging) / kUnreadable[1], std::ios::binary);  // empty
  }
  for (int i = 0; i < kImages; ++i)
  {
    cv::Mat image(kHeight, kWidth, CV_8UC1, cv::Scalar(valueOf(i)));
    image.at<uint8_t>(kHeight - 1, kWidth - 1) = static_cast<uint8_t>(i);  // not uniform, whatever the codec
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%03d.png", i);
    ASSERT_TRUE(cv::imwrite((fs::path(staging) / name).string(), image));
  }
  fs::rename(staging, folder);
}

/// Collects the latest diagnostic status per name.
class DiagnosticsWatch
{
public:
  DiagnosticsWatch() { sub_ = nh_.subscribe("/diagnostics", 50, &DiagnosticsWatch::callback, this); }
  /// Ends the subscription (waiting for a callback in progress) before the members it writes go.
  ~DiagnosticsWatch() { sub_.shutdown(); }
  /// The latest status named @p name ("ns/node: task"), if any. (Exact: "calibrated/camera" is a
  /// suffix of "uncalibrated/camera".)
  bool find(const std::string& name, diagnostic_msgs::DiagnosticStatus& out)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& s : latest_)
      if (s.name == name)
      {
        out = s;
        return true;
      }
    return false;
  }
  static std::string value(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key)
  {
    for (const auto& kv : s.values)
      if (kv.key == key)
        return kv.value;
    return std::string();
  }
  /// The value of @p key as a number; -1 when the key is missing (or not a count), which no check
  /// of a count may take for a pass.
  static long count(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key)
  {
    for (const auto& kv : s.values)
      if (kv.key == key)
      {
        char* end = nullptr;
        const long n = std::strtol(kv.value.c_str(), &end, 10);
        return !kv.value.empty() && *end == '\0' && n >= 0 ? n : -1;
      }
    return -1;
  }

private:
  void callback(const diagnostic_msgs::DiagnosticArray::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& s : msg->status)
    {
      bool replaced = false;
      for (auto& old : latest_)
        if (old.name == s.name)
        {
          old = s;
          replaced = true;
        }
      if (!replaced)
        latest_.push_back(s);
    }
  }

  ros::NodeHandle nh_;
  ros::Subscriber sub_;
  std::mutex mutex_;
  std::vector<diagnostic_msgs::DiagnosticStatus> latest_;
};

/// Collects (image, camera_info) pairs from a camera namespace.
class CameraWatch
{
public:
  explicit CameraWatch(const std::string& ns) : it_(nh_)
  {
    sub_ = it_.subscribeCamera(ns + "/image_raw", 100, &CameraWatch::callback, this);
  }
  /// Ends the subscription (waiting for a callback in progress) before the members it writes go.
  ~CameraWatch() { sub_.shutdown(); }
  size_t size()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return images_.size();
  }
  void take(std::vector<sensor_msgs::ImageConstPtr>& images, std::vector<sensor_msgs::CameraInfoConstPtr>& infos)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    images = images_;
    infos = infos_;
  }

private:
  void callback(const sensor_msgs::ImageConstPtr& image, const sensor_msgs::CameraInfoConstPtr& info)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    images_.push_back(image);
    infos_.push_back(info);
  }

  ros::NodeHandle nh_;
  image_transport::ImageTransport it_;
  image_transport::CameraSubscriber sub_;
  std::mutex mutex_;
  std::vector<sensor_msgs::ImageConstPtr> images_;
  std::vector<sensor_msgs::CameraInfoConstPtr> infos_;
};

/// Index of the test image an image message shows (-1 if none).
int imageIndex(const sensor_msgs::Image& image)
{
  if (image.data.empty())
    return -1;
  const int v = image.data.front();
  for (int i = 0; i < kImages; ++i)
    if (v == valueOf(i))
      return i;
  return -1;
}
}  // namespace

TEST(CameraPlayerNode, MissingFolderAtStartIsReportedThenPlayedOnceItAppears)
{
  DiagnosticsWatch diagnostics;
  diagnostic_msgs::DiagnosticStatus status;
  // Before the folder exists: an error naming it, while the node keeps running and retrying.
  ASSERT_TRUE(waitUntil(
      [&] { return diagnostics.find("calibrated/camera: capture", status) && status.level == status.ERROR; }, 60.0))
      << "no error diagnostics for the missing folder";
  EXPECT_NE(status.message.find(g_folder), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("does not exist"), std::string::npos) << status.message;

  // Subscribed before the folder (and so playback) is there: the first image is frame 0.
  CameraWatch camera("calibrated");
  ensureFolder();
  ASSERT_TRUE(waitUntil([&] { return camera.size() >= 3; }, 60.0)) << "no images after the folder appeared";
  {
    std::vector<sensor_msgs::ImageConstPtr> images;
    std::vector<sensor_msgs::CameraInfoConstPtr> infos;
    camera.take(images, infos);
    ASSERT_GE(images.size(), 3u);
    for (size_t k = 0; k < 3; ++k)
      EXPECT_EQ(imageIndex(*images[k]), static_cast<int>(k))
          << "image " << k << " of a subscriber from before the start";
  }
  // (OK "waiting for a subscriber to start playback" may come first, if the folder was listed
  // before the subscription was connected.)
  ASSERT_TRUE(waitUntil(
      [&]
      {
        return diagnostics.find("calibrated/camera: capture", status) && status.level == status.OK &&
               status.message == "streaming";
      },
      30.0))
      << "last status: " << status.message;
  EXPECT_EQ(DiagnosticsWatch::value(status, "state"), "streaming");
  EXPECT_EQ(DiagnosticsWatch::value(status, "reconnects"), "0");
  EXPECT_GE(DiagnosticsWatch::count(status, "frames"), 1);
  // The folder was missing at start: at least one open failed (and the key is there).
  EXPECT_GE(DiagnosticsWatch::count(status, "failed opens"), 1) << "(-1: no \"failed opens\" key)";
  EXPECT_TRUE(diagnostics.find("calibrated/camera: frame rate", status));
}

TEST(CameraPlayerNode, ImagesArriveInOrderWithCalibratedCameraInfo)
{
  ensureFolder();
  CameraWatch camera("calibrated");
  const size_t wanted = 2 * kImages + 2;
  ASSERT_TRUE(waitUntil([&] { return camera.size() >= wanted; }, 60.0)) << "got " << camera.size() << " images";
  std::vector<sensor_msgs::ImageConstPtr> images;
  std::vector<sensor_msgs::CameraInfoConstPtr> infos;
  camera.take(images, infos);
  ASSERT_EQ(images.size(), infos.size());
  for (size_t k = 0; k < images.size(); ++k)
  {
    const sensor_msgs::Image& image = *images[k];
    const sensor_msgs::CameraInfo& info = *infos[k];
    ASSERT_EQ(image.encoding, "mono8");
    ASSERT_EQ(image.width, static_cast<uint32_t>(kWidth));
    ASSERT_EQ(image.height, static_cast<uint32_t>(kHeight));
    ASSERT_EQ(image.step, static_cast<uint32_t>(kWidth));
    ASSERT_EQ(image.data.size(), static_cast<size_t>(kWidth * kHeight));
    EXPECT_EQ(image.header.frame_id, "test_camera_optical_frame");
    EXPECT_EQ(info.header.frame_id, "test_camera_optical_frame");
    EXPECT_EQ(info.header.stamp, image.header.stamp);
    EXPECT_FALSE(image.header.stamp.isZero());
    // From camera_data/camera_info.yaml.
    EXPECT_EQ(info.width, static_cast<uint32_t>(kWidth));
    EXPECT_EQ(info.height, static_cast<uint32_t>(kHeight));
    EXPECT_DOUBLE_EQ(info.K[0], 100.0);
    EXPECT_DOUBLE_EQ(info.K[2], 31.5);
    EXPECT_DOUBLE_EQ(info.K[4], 101.0);
    EXPECT_DOUBLE_EQ(info.K[5], 23.5);
    EXPECT_EQ(info.distortion_model, "plumb_bob");
    ASSERT_EQ(info.D.size(), 5u);
    EXPECT_DOUBLE_EQ(info.D[1], -0.02);

    const int index = imageIndex(image);
    ASSERT_GE(index, 0) << "image " << k << " is none of the test images (first pixel "
                        << static_cast<int>(image.data.front()) << ")";
    EXPECT_EQ(image.data.back(), index) << "the marker pixel of image " << index;
    if (k > 0)
    {
      // In name order, looping: each image is the successor of the previous one.
      EXPECT_EQ(index, (imageIndex(*images[k - 1]) + 1) % kImages) << "at message " << k;
      EXPECT_GT(image.header.stamp, images[k - 1]->header.stamp);
    }
  }
}

TEST(CameraPlayerNode, UncalibratedCameraInfoCarriesTheImageSize)
{
  ensureFolder();
  CameraWatch camera("uncalibrated");
  ASSERT_TRUE(waitUntil([&] { return camera.size() >= 3; }, 60.0));
  std::vector<sensor_msgs::ImageConstPtr> images;
  std::vector<sensor_msgs::CameraInfoConstPtr> infos;
  camera.take(images, infos);
  for (size_t k = 0; k < images.size(); ++k)
  {
    EXPECT_EQ(images[k]->header.frame_id, "camera_optical_frame");  // the default
    EXPECT_EQ(infos[k]->header.frame_id, "camera_optical_frame");
    EXPECT_EQ(infos[k]->width, static_cast<uint32_t>(kWidth));
    EXPECT_EQ(infos[k]->height, static_cast<uint32_t>(kHeight));
    EXPECT_DOUBLE_EQ(infos[k]->K[0], 0.0);
    EXPECT_GE(imageIndex(*images[k]), 0);
  }
}

TEST(CameraPlayerNode, PlayerWaitsForItsFirstSubscriberWhoGetsFrameZeroAndUnreadableFilesAreNamed)
{
  ensureFolder(g_early_folder, true);
  DiagnosticsWatch diagnostics;
  diagnostic_msgs::DiagnosticStatus status;
  // The folder is listed (open), but nothing is played before someone subscribes.
  ASSERT_TRUE(waitUntil(
      [&]
      {
        return diagnostics.find("early/camera: capture", status) &&
               status.message == "waiting for a subscriber to start playback";
      },
      60.0))
      << "the player did not wait for a subscriber; last status: " << status.message;
  EXPECT_EQ(status.level, status.OK);
  EXPECT_EQ(DiagnosticsWatch::value(status, "frames"), "0");
  EXPECT_EQ(DiagnosticsWatch::value(status, "unreadable file count"), "0");
  EXPECT_EQ(DiagnosticsWatch::value(status, "unreadable files"), "none");

  CameraWatch camera("early");
  ASSERT_TRUE(waitUntil([&] { return camera.size() >= static_cast<size_t>(kImages); }, 60.0))
      << "got " << camera.size() << " images";
  ASSERT_TRUE(waitUntil(
      [&] {
        return diagnostics.find("early/camera: capture", status) &&
               DiagnosticsWatch::value(status, "state") == "finished";
      },
      60.0))
      << "no end of playback; last status: " << status.message;
  // Every frame exactly once, from frame 0, in order; the unreadable files skipped.
  std::vector<sensor_msgs::ImageConstPtr> images;
  std::vector<sensor_msgs::CameraInfoConstPtr> infos;
  camera.take(images, infos);
  std::vector<int> indices;
  for (const auto& image : images)
    indices.push_back(imageIndex(*image));
  EXPECT_EQ(indices, (std::vector<int>{ 0, 1, 2, 3, 4 }));

  // Both unreadable files are named (with their folder), counted, and make the status a warning.
  EXPECT_EQ(status.level, status.WARN) << status.message;
  EXPECT_NE(status.message.find("2 unreadable files skipped"), std::string::npos) << status.message;
  EXPECT_EQ(DiagnosticsWatch::count(status, "unreadable file count"), 2);
  const std::string names = DiagnosticsWatch::value(status, "unreadable files");
  for (const std::string& f : kUnreadable)
    EXPECT_NE(names.find((fs::path(g_early_folder) / f).string()), std::string::npos) << names;
}

TEST(CameraPlayerNode, FolderThatNeverAppearsIsAnErrorNotACrash)
{
  DiagnosticsWatch diagnostics;
  diagnostic_msgs::DiagnosticStatus status;
  ASSERT_TRUE(waitUntil(
      [&]
      {
        return diagnostics.find("missing/camera: capture", status) && status.level == status.ERROR &&
               DiagnosticsWatch::count(status, "failed opens") >= 2;
      },
      60.0))
      << "no error with two or more failed opens (retries); \"failed opens\": "
      << DiagnosticsWatch::count(status, "failed opens") << " (-1: no such key)";
  EXPECT_NE(status.message.find("/nonexistent/sl_camera_test_frames does not exist"), std::string::npos)
      << status.message;
  EXPECT_EQ(DiagnosticsWatch::value(status, "frames"), "0");
  std::vector<std::string> nodes;
  ASSERT_TRUE(ros::master::getNodes(nodes));
  EXPECT_NE(std::find(nodes.begin(), nodes.end(), "/missing/camera"), nodes.end()) << "camera_node is gone";
}

TEST(CameraNode, InvalidParametersFailNamingThem)
{
  const std::vector<std::pair<std::string, std::string>> cases = {
    { "_backend:=player _device:=/tmp _rate:=-1", "~rate must be > 0" },
    { "_backend:=usb", "~backend must be one of v4l2, aravis, player" },
    { "_backend:=player", "~device must name a folder" },
    { "_backend:=player _device:=/tmp _camera_info_url:=http://x/c.yaml", "~camera_info_url must be" },
    { "_width:=-5", "~width must be" },
  };
  int n = 0;
  for (const auto& c : cases)
  {
    std::string out;
    const int status =
        run("rosrun sl_camera camera_node __name:=bad_camera" + std::to_string(n++) + " " + c.first, out);
    EXPECT_NE(status, 0) << c.first << ":\n" << out;
    EXPECT_NE(out.find(c.second), std::string::npos) << c.first << ":\n" << out;
  }
}

TEST(CameraNode, SizeOtherThanTheRigsFailsAtStartNamingBothSizesAndTheFile)
{
  // Checked before any device is opened: /dev/null is never read.
  std::string out;
  const int status =
      run("rosrun sl_camera camera_node __name:=bad_size_camera _backend:=v4l2 _device:=/dev/null "
          "_width:=640 _height:=400 _calibration_file:=" +
              g_rig_file,
          out);
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(out.find("640 x 400"), std::string::npos) << out;
  EXPECT_NE(out.find("752 x 480"), std::string::npos) << out;
  EXPECT_NE(out.find(g_rig_file), std::string::npos) << out;
  EXPECT_NE(out.find("~width x height"), std::string::npos) << out;
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "camera_player_rostest");
  ros::NodeHandle pnh("~");
  if (!pnh.getParam("folder", g_folder) || g_folder.empty() || !pnh.getParam("early_folder", g_early_folder) ||
      g_early_folder.empty() || !pnh.getParam("calibration_file", g_rig_file) || g_rig_file.empty())
  {
    ROS_FATAL("~folder, ~early_folder and ~calibration_file must be set");
    return 1;
  }
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  std::error_code ec;
  fs::remove_all(g_folder, ec);
  fs::remove_all(g_folder + ".staging", ec);
  fs::remove_all(g_early_folder, ec);
  fs::remove_all(g_early_folder + ".staging", ec);
  return result;
}
