// The simulated camera: renders what the rig's camera sees of a scene lit by the projector's pattern,
// from the simulated robot's pose (tf), tells the simulated robot when its bumpers touch an
// obstacle, and publishes the ground-truth collision of the robot's disc with the scene for tests.
// All image formation and geometry live in the ROS-free core (sl_sim/renderer.h, contact.h,
// collision.h).
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

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

#include "sl_sim/collision.h"
#include "sl_sim/contact.h"
#include "sl_sim/renderer.h"
#include "sl_sim/scene.h"
#include "sl_sim/sim_settings.h"
#include "sl_rig/ros/rig_param.h"
#include "sl_params/params.h"

namespace sl_sim
{

namespace
{
/// Everything the nodelet is configured with, read and validated in one place.
struct SimParams
{
  std::string rig_file;
  std::string scene_file;
  double rate = 10.0;
  double collision_rate = 20.0;
  int seed = 0;
  bool publish_depth = true;
  bool use_tf = true;
  std::string world_frame = "world";
  std::string robot_frame = "base_footprint_true";
  std::string base_frame = "base_link";
  std::string camera_frame = "camera_optical_frame";
  SimSettings settings;
  ContactSettings contact;
  sl_projector::Rig rig;
  Scene scene;
};

// The rig and the scene, loaded from their files.
void readFiles(const ros::NodeHandle& pnh, SimParams& p)
{
  // ~rig_file is the deprecated former name of ~calibration_file.
  sl_projector::RigParam rig = sl_projector::loadRigParam(pnh, "rig_file");
  p.rig_file = std::move(rig.file);
  p.rig = std::move(rig.rig);
  if (!sl_params::readIfSet(pnh, "scene_file", p.scene_file) || p.scene_file.empty())
    throw std::invalid_argument("~scene_file: required (a scene file, e.g. $(find sl_sim)/scenes/room.yaml)");
  try
  {
    p.scene = loadScene(p.scene_file);
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument(std::string("~scene_file: ") + e.what());
  }
}

// Every simulator setting, read as a parameter of its own name (defaults: @p s).
SimSettings readSimSettings(const ros::NodeHandle& pnh, SimSettings s)
{
  for (const SimSettingInfo& info : simSettingsInfo())
  {
    const double current = getSimSetting(s, info.name);
    double value = current;
    switch (info.kind)
    {
      case SimSettingInfo::Kind::Double:
        value = sl_params::read(pnh, info.name, current);
        break;
      case SimSettingInfo::Kind::Int:
        value = sl_params::read(pnh, info.name, static_cast<int>(current));
        break;
      case SimSettingInfo::Kind::Bool:
        value = sl_params::read(pnh, info.name, current != 0.0) ? 1.0 : 0.0;
        break;
    }
    setSimSetting(s, info.name, value);
  }
  return s;
}

// Runs a core type's validate(), naming the parameter as a private one.
template <typename T>
void validateParams(const T& value)
{
  try
  {
    value.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
}

SimParams readParams(const ros::NodeHandle& pnh)
{
  SimParams p;
  readFiles(pnh, p);
  p.rate = sl_params::read(pnh, "rate", p.rate);
  if (!std::isfinite(p.rate) || p.rate <= 0.0 || p.rate > 1000.0)
    throw std::invalid_argument("~rate: must be in (0, 1000] Hz, got " + std::to_string(p.rate));
  p.collision_rate = sl_params::read(pnh, "collision_rate", p.collision_rate);
  if (!std::isfinite(p.collision_rate) || p.collision_rate <= 0.0 || p.collision_rate > 1000.0)
    throw std::invalid_argument("~collision_rate: must be in (0, 1000] Hz, got " + std::to_string(p.collision_rate));
  p.seed = sl_params::read(pnh, "seed", p.seed);
  if (p.seed < 0)
    throw std::invalid_argument("~seed: must be >= 0, got " + std::to_string(p.seed));
  p.publish_depth = sl_params::read(pnh, "publish_depth", p.publish_depth);
  p.use_tf = sl_params::read(pnh, "use_tf", p.use_tf);
  p.world_frame = sl_params::read(pnh, "world_frame", p.world_frame);
  p.robot_frame = sl_params::read(pnh, "robot_frame", p.robot_frame);
  p.base_frame = sl_params::read(pnh, "base_frame", p.base_frame);
  p.camera_frame = sl_params::read(pnh, "camera_frame", p.camera_frame);
  for (const std::string* f : { &p.world_frame, &p.robot_frame, &p.base_frame, &p.camera_frame })
    if (f->empty())
      throw std::invalid_argument("~world_frame, ~robot_frame, ~base_frame and ~camera_frame must not be empty");
  p.settings = readSimSettings(pnh, p.settings);
  validateParams(p.settings);
  p.contact.robot_radius = sl_params::read(pnh, "robot_radius", p.contact.robot_radius);
  p.contact.robot_height = sl_params::read(pnh, "robot_height", p.contact.robot_height);
  p.contact.contact_min_height = sl_params::read(pnh, "contact_min_height", p.contact.contact_min_height);
  validateParams(p.contact);
  return p;
}

// A message holding a copy of a continuous image (the renderer's outputs are).
sensor_msgs::ImagePtr toImageMsg(const cv::Mat& image, const std::string& encoding, const std_msgs::Header& header)
{
  sensor_msgs::ImagePtr msg(new sensor_msgs::Image);
  msg->header = header;
  msg->height = static_cast<uint32_t>(image.rows);
  msg->width = static_cast<uint32_t>(image.cols);
  msg->encoding = encoding;
  msg->is_bigendian = 0;
  msg->step = static_cast<uint32_t>(image.cols * image.elemSize());
  msg->data.assign(image.data, image.data + image.total() * image.elemSize());
  return msg;
}

Eigen::Isometry3d translationX(double x)
{
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation().x() = x;
  return t;
}
}  // namespace

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
    info_ = cameraInfo();
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

  sensor_msgs::CameraInfo cameraInfo() const
  {
    const sl_projector::PinholeModel& c = p_.rig.camera;
    sensor_msgs::CameraInfo info;
    info.header.frame_id = p_.camera_frame;
    info.width = static_cast<uint32_t>(c.width);
    info.height = static_cast<uint32_t>(c.height);
    info.distortion_model = "plumb_bob";
    info.D.assign(c.dist.begin(), c.dist.end());
    info.K = { c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0 };
    info.R = { 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0 };
    info.P = { c.fx, 0.0, c.cx, 0.0, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0 };
    return info;
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
    // Default: platform_edge at the world origin, so the robot's centre is robot_radius behind it.
    robot_in_world = translationX(-p_.contact.robot_radius);
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
    Eigen::Isometry3d camera_in_base =
        translationX(p_.contact.robot_radius) * toIsometry(p_.rig.mount.cameraOpticalInParent());
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

  /// The moment the image shows: the time of the robot pose it is rendered from (so that a
  /// consumer's tf lookup at the stamp finds the pose of the exposure), or now when that pose is
  /// missing, stale (> 0.2 s) or not newer than the last frame's stamp.
  ros::Time exposureStamp(const ros::Time& pose_stamp)
  {
    const ros::Time now = ros::Time::now();
    ros::Time stamp = now;
    if (!pose_stamp.isZero() && pose_stamp <= now && (now - pose_stamp).toSec() <= 0.2 && pose_stamp > last_stamp_)
      stamp = pose_stamp;
    last_stamp_ = std::max(last_stamp_, stamp);
    return stamp;
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
    const ros::Time stamp = exposureStamp(pose_stamp);
    try
    {
      // A different noise seed every frame, the same sequence for the same ~seed.
      renderer_->render(p_.scene, pattern_, camera_in_world,
                        static_cast<uint64_t>(p_.seed) * 0x100000001ULL + frame_count_++, out_);
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
    sl_msgs::CollisionPtr msg(new sl_msgs::Collision);
    msg->header.stamp = pose_stamp.isZero() ? ros::Time::now() : pose_stamp;
    msg->header.frame_id = p_.world_frame;
    msg->colliding = collision_.colliding;
    msg->objects = collision_.names;
    msg->min_clearance = collision_.min_clearance;
    msg->nearest_object = collision_.nearest_name;
    collision_pub_.publish(msg);
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
  ros::Time last_stamp_;
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
