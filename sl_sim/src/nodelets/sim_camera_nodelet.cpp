// The simulated camera: renders what the rig's camera sees of a scene lit by the projector's pattern,
// from the simulated robot's pose (tf), tells the simulated robot when its bumpers touch an
// obstacle, and publishes the ground-truth collision of the robot's disc with the scene for tests.
// All image formation and geometry live in the ROS-free core (sl_sim/renderer.h, contact.h,
// collision.h).
#include <memory>
#include <string>

#include <cv_bridge/cv_bridge.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <sl_msgs/Collision.h>
#include <std_msgs/UInt8.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "messages.h"
#include "params.h"
#include "sl_sim/camera_frames.h"
#include "sl_sim/collision.h"
#include "sl_sim/contact.h"
#include "sl_sim/renderer.h"

namespace sl_sim
{

/**
 * Simulated structured-light camera: subscribes `pattern` (the projector's frame), renders the scene
 * from the robot's pose in tf at `rate` while anyone listens, publishes `image_raw` + `camera_info`,
 * `depth/image_raw` + `depth/camera_info` (REP 118 ground truth) and, always, `contact` (bump bits)
 * and `collision` (sl_msgs/Collision, at every frame tick and at `collision_rate`).
 */
class SimCameraNodelet : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try
    {
      p_ = readParams(pnh);
      renderer_.reset(new Renderer(p_.rig, p_.settings));
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }
    info_ = toCameraInfo(p_.rig.camera, p_.camera_frame);
    tf_buffer_.reset(new tf2_ros::Buffer());
    if (p_.use_tf)
      tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh));
    it_.reset(new image_transport::ImageTransport(nh));
    image_pub_ = it_->advertiseCamera("image_raw", 1);
    if (p_.publish_depth)
      depth_pub_ = it_->advertiseCamera("depth/image_raw", 1);
    contact_pub_ = nh.advertise<std_msgs::UInt8>("contact", 10);
    collision_pub_ = nh.advertise<sl_msgs::Collision>("collision", 20);
    pattern_sub_ = nh.subscribe("pattern", 1, &SimCameraNodelet::onPattern, this);
    timer_ = nh.createTimer(ros::Duration(1.0 / p_.rate), &SimCameraNodelet::onTimer, this);
    // The collision check costs microseconds: at its own rate, so that it does not depend on the frames'.
    collision_timer_ =
        nh.createTimer(ros::Duration(1.0 / p_.collision_rate), &SimCameraNodelet::onCollisionTimer, this);
    NODELET_INFO("simulating a %d x %d camera at %.1f Hz: rig %s, scene %s (%zu objects), pattern from %s",
                 p_.rig.camera.width, p_.rig.camera.height, p_.rate, p_.rig_file.c_str(), p_.scene_file.c_str(),
                 p_.scene.objects.size(), pattern_sub_.getTopic().c_str());
  }

  void onPattern(const sensor_msgs::ImageConstPtr& msg)
  {
    cv::Mat frame;
    try
    {
      if (msg->encoding == sensor_msgs::image_encodings::MONO8)
        frame = cv_bridge::toCvShare(msg)->image.clone();
      else
      {
        frame = cv_bridge::toCvCopy(msg, sensor_msgs::image_encodings::MONO8)->image;
        NODELET_WARN_THROTTLE(10.0, "pattern: converted encoding '%s' to mono8", msg->encoding.c_str());
      }
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_THROTTLE(5.0, "pattern: cannot use an image of encoding '%s' (need mono8): %s",
                             msg->encoding.c_str(), e.what());
      return;
    }
    if (frame.cols != p_.rig.projector.width || frame.rows != p_.rig.projector.height)
    {
      NODELET_ERROR_THROTTLE(5.0, "pattern: %d x %d px, but the rig's projector is %d x %d px; ignored", frame.cols,
                             frame.rows, p_.rig.projector.width, p_.rig.projector.height);
      return;
    }
    pattern_ = frame;
  }

  /// The robot (base footprint) in the world, from tf or the static default; @p pose_stamp is the
  /// time of the pose (zero for the default). @return what tf lacks (empty when nothing).
  std::string robotPose(Eigen::Isometry3d& robot_in_world, ros::Time& pose_stamp)
  {
    pose_stamp = ros::Time();
    robot_in_world = defaultRobotInWorld(p_.contact.robot_radius);
    if (!p_.use_tf)
      return std::string();
    try
    {
      const geometry_msgs::TransformStamped robot =
          tf_buffer_->lookupTransform(p_.world_frame, p_.robot_frame, ros::Time(0));
      robot_in_world = tf2::transformToEigen(robot);
      pose_stamp = robot.header.stamp;
    }
    catch (const tf2::TransformException& e)
    {
      return std::string(" ") + e.what();
    }
    return std::string();
  }

  /// Robot (base footprint) and camera optical frame in the world, from tf or the static default;
  /// @p pose_stamp is the time of the robot's pose (zero for the default).
  void poses(Eigen::Isometry3d& robot_in_world, Eigen::Isometry3d& camera_in_world, ros::Time& pose_stamp)
  {
    std::string missing = robotPose(robot_in_world, pose_stamp);
    Eigen::Isometry3d camera_in_base = defaultCameraInBase(p_.rig, p_.contact.robot_radius);
    if (p_.use_tf)
    {
      try
      {
        camera_in_base =
            tf2::transformToEigen(tf_buffer_->lookupTransform(p_.base_frame, p_.camera_frame, ros::Time(0)));
      }
      catch (const tf2::TransformException& e)
      {
        missing += std::string(" ") + e.what();
      }
      if (!missing.empty())
        NODELET_WARN_THROTTLE(10.0,
                              "tf: falling back to the default pose (platform_edge at the world origin, camera on the "
                              "rig's mount) for what is missing:%s",
                              missing.c_str());
    }
    camera_in_world = robot_in_world * camera_in_base;
  }

  void onTimer(const ros::TimerEvent&)
  {
    Eigen::Isometry3d robot_in_world, camera_in_world;
    ros::Time pose_stamp;
    poses(robot_in_world, camera_in_world, pose_stamp);

    // Contact and collision from the same pose.
    std_msgs::UInt8 contact;
    contact.data = computeContact(p_.scene, robot_in_world, p_.contact);
    contact_pub_.publish(contact);
    publishCollision(robot_in_world, pose_stamp);

    const bool want_image = image_pub_.getNumSubscribers() > 0;
    const bool want_depth = p_.publish_depth && depth_pub_.getNumSubscribers() > 0;
    if (!want_image && !want_depth)
      return;
    if (pattern_.empty())
    {
      NODELET_WARN_THROTTLE(10.0, "no pattern received yet on %s: not rendering", pattern_sub_.getTopic().c_str());
      return;
    }
    // The time of the pose the image is rendered from, so that a consumer's tf lookup at the stamp
    // finds the pose of the exposure (ExposureStamper: now when that pose is missing or stale).
    ros::Time stamp;
    stamp.fromNSec(static_cast<uint64_t>(
        stamper_.stamp(static_cast<int64_t>(pose_stamp.toNSec()), static_cast<int64_t>(ros::Time::now().toNSec()))));
    try
    {
      // A different noise seed every frame, the same sequence for the same ~seed.
      renderer_->render(p_.scene, pattern_, camera_in_world, frameSeed(p_.seed, frame_count_++), out_);
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_THROTTLE(5.0, "rendering failed: %s", e.what());
      return;
    }
    sensor_msgs::CameraInfo info = info_;
    info.header.stamp = stamp;
    if (want_image)
      image_pub_.publish(toImageMsg(out_.image, sensor_msgs::image_encodings::MONO8, info.header),
                         sensor_msgs::CameraInfoPtr(new sensor_msgs::CameraInfo(info)));
    if (want_depth)
      depth_pub_.publish(toImageMsg(out_.depth, sensor_msgs::image_encodings::TYPE_32FC1, info.header),
                         sensor_msgs::CameraInfoPtr(new sensor_msgs::CameraInfo(info)));
  }

  void onCollisionTimer(const ros::TimerEvent&)
  {
    Eigen::Isometry3d robot_in_world;
    ros::Time pose_stamp;
    robotPose(robot_in_world, pose_stamp);  // onTimer() warns about what tf lacks
    publishCollision(robot_in_world, pose_stamp);
  }

  /// The ground-truth collision of the robot at @p robot_in_world, stamped with its pose's time.
  void publishCollision(const Eigen::Isometry3d& robot_in_world, const ros::Time& pose_stamp)
  {
    computeCollision(p_.scene, robot_in_world, p_.contact, collision_);
    collision_pub_.publish(
        toCollisionMsg(collision_, pose_stamp.isZero() ? ros::Time::now() : pose_stamp, p_.world_frame));
    if (collision_.colliding)
      NODELET_WARN_THROTTLE(1.0,
                            "collision: the robot's disc at (%.3f, %.3f) overlaps %zu object(s), deepest %s (%.4f m)",
                            robot_in_world.translation().x(), robot_in_world.translation().y(),
                            collision_.objects.size(), collision_.nearest_name.c_str(), collision_.min_clearance);
  }

  SimParams p_;
  CollisionReport collision_;
  std::unique_ptr<Renderer> renderer_;
  RenderOutput out_;
  sensor_msgs::CameraInfo info_;
  cv::Mat pattern_;
  uint64_t frame_count_ = 0;
  ExposureStamper stamper_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::CameraPublisher image_pub_;
  image_transport::CameraPublisher depth_pub_;
  ros::Publisher contact_pub_;
  ros::Publisher collision_pub_;
  ros::Subscriber pattern_sub_;
  ros::Timer timer_;
  ros::Timer collision_timer_;
};

}  // namespace sl_sim

PLUGINLIB_EXPORT_CLASS(sl_sim::SimCameraNodelet, nodelet::Nodelet)
