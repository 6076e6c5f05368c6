// Checks the camera nodelet with the aravis back-end against Aravis' simulated camera: images of the
// configured size in the configured frame, paired camera_info, increasing stamps, diagnostics.
#include <gtest/gtest.h>

#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sl_testing/rostest_main.h>
#include <sl_testing/wait.h>

using sl_testing::waitUntil;

namespace
{
std::string valueOf(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key)
{
  for (const auto& kv : s.values)
    if (kv.key == key)
      return kv.value;
  return std::string();
}
}  // namespace

TEST(CameraAravisNode, StreamsTheFakeCameraWithCameraInfoAndDiagnostics)
{
  ros::NodeHandle nh;
  image_transport::ImageTransport it(nh);
  std::mutex mutex;
  std::vector<sensor_msgs::ImageConstPtr> images;
  std::vector<sensor_msgs::CameraInfoConstPtr> infos;
  image_transport::CameraSubscriber sub =
      it.subscribeCamera("aravis/image_raw", 100,
                         [&](const sensor_msgs::ImageConstPtr& image, const sensor_msgs::CameraInfoConstPtr& info)
                         {
                           std::lock_guard<std::mutex> lock(mutex);
                           images.push_back(image);
                           infos.push_back(info);
                         });
  diagnostic_msgs::DiagnosticStatus capture;
  bool have_capture = false;
  ros::Subscriber diag_sub =
      nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 50,
                                                     [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& msg)
                                                     {
                                                       std::lock_guard<std::mutex> lock(mutex);
                                                       for (const auto& s : msg->status)
                                                         if (s.name == "aravis/camera: capture")
                                                         {
                                                           capture = s;
                                                           have_capture = true;
                                                         }
                                                     });

  ASSERT_TRUE(waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(mutex);
        return images.size() >= 10;
      },
      60.0))
      << "no images from the fake camera";
  ASSERT_TRUE(waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(mutex);
        return have_capture && capture.level == capture.OK && valueOf(capture, "frames") != "0";
      },
      30.0));

  std::lock_guard<std::mutex> lock(mutex);
  for (size_t k = 0; k < images.size(); ++k)
  {
    EXPECT_EQ(images[k]->encoding, "mono8");
    EXPECT_EQ(images[k]->width, 64u);
    EXPECT_EQ(images[k]->height, 48u);
    EXPECT_EQ(images[k]->data.size(), 64u * 48u);
    EXPECT_EQ(images[k]->header.frame_id, "fake_camera_optical_frame");
    EXPECT_EQ(infos[k]->header.stamp, images[k]->header.stamp);
    EXPECT_EQ(infos[k]->width, 64u);
    EXPECT_EQ(infos[k]->height, 48u);
    if (k > 0)
    {
      EXPECT_GT(images[k]->header.stamp, images[k - 1]->header.stamp);
    }
  }
  EXPECT_EQ(capture.message, "streaming");
  EXPECT_EQ(capture.hardware_id, "aravis:Fake_1");
  EXPECT_EQ(valueOf(capture, "device rate (Hz)"), "25");
  EXPECT_EQ(valueOf(capture, "reconnects"), "0");
  EXPECT_EQ(valueOf(capture, "failed opens"), "0");
  EXPECT_FALSE(valueOf(capture, "dropped frames").empty());
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "camera_aravis_rostest");
}
