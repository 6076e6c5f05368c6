// The camera nodelet (aravis back-end) against Aravis' GigE Vision fake camera, which this client
// starts, kills and restarts: full-frame mono8 at the set rate, settings read back from the device
// with arv-tool, an ERROR diagnostic soon after the camera dies, images again soon after it returns,
// and streaming with 1 % of the packets lost (resent on request). The tests run in order.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sl_testing/process.h>
#include <sl_testing/wait.h>

extern char** environ;

using sl_testing::waitUntil;

namespace
{
std::string g_serial;
double g_rate = 10.0;
double g_exposure = 0.0;
double g_gain = 0.0;
pid_t g_camera = -1;

/// Starts arv-fake-gv-camera-0.8 on 127.0.0.1; @p loss_per_thousand packets are dropped.
pid_t startCamera(int loss_per_thousand)
{
  std::vector<std::string> args{ "arv-fake-gv-camera-0.8", "-i", "127.0.0.1", "-s", g_serial };
  if (loss_per_thousand > 0)
  {
    args.push_back("-r");
    args.push_back(std::to_string(loss_per_thousand));
  }
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(&a[0]);
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0)
    return -1;
  return pid;
}

void killCamera()
{
  if (g_camera > 0)
  {
    ::kill(g_camera, SIGKILL);
    ::waitpid(g_camera, nullptr, 0);
    g_camera = -1;
  }
}

/// Output of a command (stdout and stderr).
std::string run(const std::string& command)
{
  std::string out;
  sl_testing::run(command, out);
  return out;
}

/// Value of "Feature = value ..." in arv-tool's output; NaN when absent.
double featureValue(const std::string& output, const std::string& feature)
{
  std::istringstream in(output);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(feature + " = ", 0) == 0)
      return std::atof(line.c_str() + feature.size() + 3);
  return std::nan("");
}

std::string valueOf(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key)
{
  for (const auto& kv : s.values)
    if (kv.key == key)
      return kv.value;
  return std::string();
}

/// Images and the capture / frame rate diagnostics of gv/camera, with wall arrival times.
class Watch
{
public:
  Watch()
  {
    images_sub_ = nh_.subscribe("gv/image_raw", 100, &Watch::onImage, this);
    diag_sub_ = nh_.subscribe("/diagnostics", 100, &Watch::onDiagnostics, this);
  }
  void onImage(const sensor_msgs::ImageConstPtr& image)
  {
    std::lock_guard<std::mutex> lock(mutex);
    images.push_back(image);
    image_times.push_back(ros::WallTime::now());
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& s : msg->status)
    {
      if (s.name == "gv/camera: capture")
      {
        capture = s;
        captures.emplace_back(ros::WallTime::now(), s);
      }
      if (s.name == "gv/camera: frame rate")
        rate = s;
    }
  }
  size_t imageCount()
  {
    std::lock_guard<std::mutex> lock(mutex);
    return images.size();
  }

  std::mutex mutex;
  std::vector<sensor_msgs::ImageConstPtr> images;
  std::vector<ros::WallTime> image_times;
  diagnostic_msgs::DiagnosticStatus capture, rate;
  std::vector<std::pair<ros::WallTime, diagnostic_msgs::DiagnosticStatus>> captures;

private:
  ros::NodeHandle nh_;
  ros::Subscriber images_sub_, diag_sub_;
};

Watch* g_watch = nullptr;

/// Waits for @p n more images and checks them: complete 752 x 480 mono8, at the set rate (stamps).
void expectFullFramesAtRate(size_t n, double period_tolerance)
{
  const size_t start = g_watch->imageCount();
  ASSERT_TRUE(waitUntil([&] { return g_watch->imageCount() >= start + n; }, 60.0))
      << "only " << g_watch->imageCount() - start << " of " << n << " images";
  std::lock_guard<std::mutex> lock(g_watch->mutex);
  const auto& images = g_watch->images;
  for (size_t k = start; k < start + n; ++k)
  {
    EXPECT_EQ(images[k]->encoding, "mono8");
    EXPECT_EQ(images[k]->width, 752u);
    EXPECT_EQ(images[k]->height, 480u);
    EXPECT_EQ(images[k]->step, 752u);
    EXPECT_EQ(images[k]->data.size(), 752u * 480u);
    EXPECT_EQ(images[k]->header.frame_id, "gv_camera_optical_frame");
  }
  // Device-paced stamps: the mean period over the images, near the set rate's.
  const double span = (images[start + n - 1]->header.stamp - images[start]->header.stamp).toSec();
  const double period = span / static_cast<double>(n - 1);
  std::printf("[ MEASURED ] mean period of %zu images %.4f s\n", n, period);
  EXPECT_NEAR(period, 1.0 / g_rate, period_tolerance / g_rate) << "mean period of " << n << " images";
}
}  // namespace

TEST(CameraFakeGv, StreamsFullFrameMono8AtTheSetRate)
{
  g_camera = startCamera(0);
  ASSERT_GT(g_camera, 0) << "cannot start arv-fake-gv-camera-0.8 (install aravis-tools)";
  expectFullFramesAtRate(30, 0.05);
  ASSERT_TRUE(waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(g_watch->mutex);
        return g_watch->capture.level == diagnostic_msgs::DiagnosticStatus::OK &&
               g_watch->rate.level == diagnostic_msgs::DiagnosticStatus::OK;
      },
      20.0));
  std::lock_guard<std::mutex> lock(g_watch->mutex);
  EXPECT_EQ(g_watch->capture.message, "streaming");
  EXPECT_EQ(valueOf(g_watch->capture, "device rate (Hz)"), "10");
  // The stream may start in the middle of a frame: at most that one is incomplete.
  EXPECT_LE(std::atoi(valueOf(g_watch->capture, "dropped frames").c_str()), 1)
      << valueOf(g_watch->capture, "last error");
  EXPECT_EQ(valueOf(g_watch->capture, "reconnects"), "0");
}

TEST(CameraFakeGv, ExposureAndGainAreReadBackFromTheDevice)
{
  ASSERT_GT(g_camera, 0);
  const std::string out = run("arv-tool-0.8 -n Aravis-Fake-" + g_serial + " control ExposureTimeAbs GainRaw");
  EXPECT_DOUBLE_EQ(featureValue(out, "ExposureTimeAbs"), g_exposure * 1e6) << out;
  EXPECT_DOUBLE_EQ(featureValue(out, "GainRaw"), g_gain) << out;
}

TEST(CameraFakeGv, AKilledCameraIsAnError)
{
  ASSERT_GT(g_camera, 0);
  ASSERT_TRUE(waitUntil([&] { return g_watch->imageCount() >= 40; }, 30.0));
  const ros::WallTime killed = ros::WallTime::now();
  killCamera();
  // An ERROR on /diagnostics after the camera's death (the delay is printed: on a shared machine the
  // wait's bound only tells an error from none).
  ros::WallTime error_at;
  ASSERT_TRUE(waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(g_watch->mutex);
        for (const auto& c : g_watch->captures)
          if (c.first > killed && c.second.level == diagnostic_msgs::DiagnosticStatus::ERROR)
          {
            error_at = c.first;
            return true;
          }
        return false;
      },
      10.0))
      << "no ERROR diagnostic after the camera was killed";
  const double delay = (error_at - killed).toSec();
  std::printf("[ MEASURED ] ERROR diagnostic %.2f s after the camera was killed\n", delay);
}

TEST(CameraFakeGv, ARestartedCameraStreamsAgain)
{
  // Restarted with 1 % of its stream packets lost, which the next test streams with.
  const size_t before = g_watch->imageCount();
  const ros::WallTime started = ros::WallTime::now();
  g_camera = startCamera(10);
  ASSERT_GT(g_camera, 0);
  ASSERT_TRUE(waitUntil([&] { return g_watch->imageCount() > before; }, 30.0)) << "no images after the restart";
  double delay = 0.0;
  {
    std::lock_guard<std::mutex> lock(g_watch->mutex);
    delay = (g_watch->image_times[before] - started).toSec();
  }
  std::printf("[ MEASURED ] first image %.2f s after the camera was restarted\n", delay);
}

TEST(CameraFakeGv, StreamsFullFramesWithOnePercentPacketLoss)
{
  ASSERT_GT(g_camera, 0);
  const double frames_before = []
  {
    std::lock_guard<std::mutex> lock(g_watch->mutex);
    return std::atof(valueOf(g_watch->capture, "frames").c_str()) +
           std::atof(valueOf(g_watch->capture, "dropped frames").c_str());
  }();
  const double dropped_before = []
  {
    std::lock_guard<std::mutex> lock(g_watch->mutex);
    return std::atof(valueOf(g_watch->capture, "dropped frames").c_str());
  }();
  // Aravis' fake camera does not answer resend requests: a frame that lost a packet is incomplete.
  // Few large packets per frame keep most frames whole; the mean period grows by the lost ones.
  expectFullFramesAtRate(50, 0.5);
  ros::WallDuration(1.5).sleep();  // one more diagnostics message
  std::lock_guard<std::mutex> lock(g_watch->mutex);
  const double frames = std::atof(valueOf(g_watch->capture, "frames").c_str()) +
                        std::atof(valueOf(g_watch->capture, "dropped frames").c_str()) - frames_before;
  const double dropped = std::atof(valueOf(g_watch->capture, "dropped frames").c_str()) - dropped_before;
  std::printf("[ MEASURED ] with 1 %% packet loss: %.0f frames, %.0f of them incomplete\n", frames, dropped);
  // 752 x 480 in packets of at most 16404 bytes (the fake camera's limit): 25 packets a frame, of
  // which all arrive in 0.99^25 = 78 % of the frames; measured about 70 %. With the fake camera's
  // default 1400-byte packets it was 7 %.
  EXPECT_LE(dropped, 0.5 * frames);
  // The one reconnect is the restart after the kill: the lossy stream itself never stalled.
  EXPECT_EQ(valueOf(g_watch->capture, "reconnects"), "1") << "the lossy stream must not stall";
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "camera_fake_gv_rostest");
  ros::NodeHandle pnh("~");
  pnh.param("serial", g_serial, std::string("SLTEST16"));
  pnh.param("rate", g_rate, 10.0);
  pnh.param("exposure", g_exposure, 0.005);
  pnh.param("gain", g_gain, 3.0);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Watch watch;
  g_watch = &watch;
  const int result = RUN_ALL_TESTS();
  killCamera();
  return result;
}
