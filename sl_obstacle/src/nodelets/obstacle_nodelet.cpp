// The sl_obstacle/obstacle nodelet: ROS adapter of the Supervisor (sl_obstacle_core), which decides.
// Subscribes `points` (through a tf2 message filter into ~target_frame) and, with ~use_map, `ray_ends`
// (into ~odom_frame), `hazards` and `cmd_vel_in` (`_stamped`), and hands them to the supervisor with
// their stamps; RobotLink sends what it returns, Display shows `markers` and `local_map`. All
// callbacks share one mutex; nothing blocks in onInit.
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <message_filters/subscriber.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sl_msgs/Hazards.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_listener.h>

#include "cloud_conversion.h"
#include "markers.h"
#include "params.h"
#include "robot_link.h"
#include "sl_obstacle/supervisor.h"

namespace sl_obstacle
{
class ObstacleNodelet : public nodelet::Nodelet
{
public:
  ~ObstacleNodelet() override
  {
    // Stop callbacks before the members they use go away. A tf filter goes before the subscriber
    // that feeds it: its destructor disconnects from that subscriber's signal (whose mutex would be
    // gone, and the manager aborts with boost::lock_error).
    timer_.stop();
    tf_filter_.reset();
    cloud_sub_.reset();
    rays_filter_.reset();
    rays_sub_.reset();
  }

private:
  using Cloud = sensor_msgs::PointCloud2;

  void onInit() override;
  void subscribeMap();
  void onReconfigure(ObstacleConfig& config, uint32_t level);
  void onCloud(const Cloud::ConstPtr& cloud);
  void onFilterFailure(const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason);
  void processCloud(const Cloud::ConstPtr& cloud);
  void onRays(const Cloud::ConstPtr& cloud);
  /// Converts the clouds of one image into map rays and gives them to the supervisor.
  void insertRays(const RayInsert& insert);
  void onHazards(const sl_msgs::Hazards& msg);
  void onCommand(const geometry_msgs::Twist& twist, const ros::Time& stamp);
  void onGoalResult(unsigned id, GoalEnd end, const std::string& what);
  void onTimer(const ros::TimerEvent& event);
  /// Sends what the supervisor returned (RobotLink). Caller holds mutex_.
  void carryOut(const Actions& actions, const ros::Time& now);

  std::recursive_mutex mutex_;
  NodeletParams params_;
  std::unique_ptr<RobotLink> link_;
  std::unique_ptr<Display> display_;
  std::unique_ptr<Supervisor> sup_;
  std::vector<Point> points_;  // the newest cloud in ~target_frame
  std::vector<MapRay> rays_;
  ros::Time cloud_stamp_;  // the newest cloud's stamp (exact, for the status)
  ros::Time map_stamp_;    // the newest ray cloud in the map

  ros::NodeHandle nh_, pnh_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<message_filters::Subscriber<Cloud>> cloud_sub_, rays_sub_;
  std::unique_ptr<tf2_ros::MessageFilter<Cloud>> tf_filter_, rays_filter_;
  ros::Subscriber hazards_sub_, command_sub_, stamped_command_sub_;
  ros::Timer timer_;
  std::unique_ptr<dynamic_reconfigure::Server<ObstacleConfig>> reconfigure_;
  boost::recursive_mutex reconfigure_mutex_;
  bool reconfigure_ready_ = false;
};

void ObstacleNodelet::onInit()
{
  nh_ = getNodeHandle();
  pnh_ = getPrivateNodeHandle();
  try
  {
    params_ = loadParams(pnh_);
  }
  catch (const std::invalid_argument& e)
  {
    NODELET_FATAL("%s", e.what());
    throw;
  }
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  link_ = std::make_unique<RobotLink>(
      nh_, getName(), params_, *tf_buffer_,
      [this](unsigned id, GoalEnd end, const std::string& what) { onGoalResult(id, end, what); },
      [this](unsigned id, double remaining)
      {
        std::lock_guard<std::recursive_mutex> lock(mutex_);
        sup_->onGoalFeedback(id, remaining);
      });
  sup_ = std::make_unique<Supervisor>(params_.settings, params_.command_mode, *link_);
  display_ = std::make_unique<Display>(nh_, params_, sup_->world() != nullptr);

  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh_);
  cloud_sub_ = std::make_unique<message_filters::Subscriber<Cloud>>();
  cloud_sub_->subscribe(nh_, "points", 2);
  cloud_sub_->registerCallback(&ObstacleNodelet::onCloud, this);
  tf_filter_ = std::make_unique<tf2_ros::MessageFilter<Cloud>>(*tf_buffer_, params_.target_frame, 5, nh_);
  tf_filter_->registerCallback(&ObstacleNodelet::processCloud, this);
  tf_filter_->registerFailureCallback([this](const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason)
                                      { onFilterFailure(cloud, reason); });
  if (sup_->world())
    subscribeMap();

  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<ObstacleConfig>>(reconfigure_mutex_, pnh_);
  reconfigure_->setCallback([this](ObstacleConfig& config, uint32_t level) { onReconfigure(config, level); });
  reconfigure_ready_ = true;

  timer_ = nh_.createTimer(ros::Duration(1.0 / params_.control_rate), &ObstacleNodelet::onTimer, this);
  NODELET_INFO("obstacle: volume W %.3f x H %.3f x B %.3f m in %s, command_mode %s%s",
               params_.settings.checker.volume.width, params_.settings.checker.volume.height,
               params_.settings.checker.volume.depth, params_.target_frame.c_str(), toString(params_.command_mode),
               sup_->world() ? ", cmd_vel_in filtered" : " (no map: cmd_vel_in ignored)");
}

void ObstacleNodelet::subscribeMap()
{
  hazards_sub_ = nh_.subscribe("hazards", 10, &ObstacleNodelet::onHazards, this);
  rays_sub_ = std::make_unique<message_filters::Subscriber<Cloud>>(nh_, "ray_ends", 2);
  rays_filter_ = std::make_unique<tf2_ros::MessageFilter<Cloud>>(*rays_sub_, *tf_buffer_, params_.odom_frame, 5, nh_);
  rays_filter_->registerCallback(&ObstacleNodelet::onRays, this);
  rays_filter_->registerFailureCallback([this](const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason)
                                        { onFilterFailure(cloud, reason); });
  command_sub_ = nh_.subscribe<geometry_msgs::Twist>(
      "cmd_vel_in", 1, [this](const geometry_msgs::TwistConstPtr& msg) { onCommand(*msg, ros::Time::now()); });
  stamped_command_sub_ = nh_.subscribe<geometry_msgs::TwistStamped>(
      "cmd_vel_in_stamped", 1,
      [this](const geometry_msgs::TwistStampedConstPtr& msg)
      {
        if (msg->header.stamp.isZero())
          NODELET_WARN_THROTTLE(2.0, "refusing a cmd_vel_in_stamped command without a stamp (header.stamp 0)");
        else
          onCommand(msg->twist, std::min(msg->header.stamp, ros::Time::now()));
      });
}

void ObstacleNodelet::onReconfigure(ObstacleConfig& config, uint32_t /*level*/)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const std::string e = reconfigure_ready_ ? reconfigureError(config, params_.config) : "";
  if (!reconfigure_ready_ || !e.empty())
  {
    // The server's first call carries the start-up parameters, already checked by loadParams().
    if (!e.empty())
      NODELET_ERROR("reconfigure refused, keeping the previous values: %s", e.c_str());
    config = params_.config;
    return;
  }
  const bool new_map = sup_->world() && changesWorld(config, params_.config);
  params_.settings = toSettings(config);
  sup_->setSettings(params_.settings, new_map);
  if (new_map)
  {
    map_stamp_ = ros::Time();  // the new map holds no image yet
    NODELET_WARN("map parameters changed: the local map starts empty");
  }
  params_.config = config;
  NODELET_INFO("reconfigured");
}

void ObstacleNodelet::onCloud(const Cloud::ConstPtr& cloud)
{
  if (cloud->header.stamp.isZero())
    NODELET_WARN_THROTTLE(2.0, "refusing a cloud without a stamp (header.stamp 0): its age is unknown");
  else if (cloud->header.frame_id == params_.target_frame)
    processCloud(cloud);  // already in the working-volume frame: no transform needed
  else
    tf_filter_->add(cloud);
}

void ObstacleNodelet::onFilterFailure(const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason)
{
  NODELET_WARN_THROTTLE(2.0, "dropping cloud in frame '%s' at %.3f: no transform to '%s' (%s)",
                        cloud->header.frame_id.c_str(), cloud->header.stamp.toSec(), params_.target_frame.c_str(),
                        toString(reason));
}

void ObstacleNodelet::processCloud(const Cloud::ConstPtr& cloud)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  geometry_msgs::Transform transform;
  transform.rotation.w = 1.0;
  std::string e;
  if (cloud->header.frame_id != params_.target_frame &&
      !transformAt(*tf_buffer_, params_.target_frame, cloud->header, transform, e))
  {
    NODELET_WARN_THROTTLE(2.0, "dropping cloud: %s", e.c_str());
    return;
  }
  if (!(e = convertCloud(*cloud, transform, points_)).empty())
  {
    NODELET_ERROR_THROTTLE(2.0, "dropping cloud in frame '%s': %s", cloud->header.frame_id.c_str(), e.c_str());
    return;
  }
  cloud_stamp_ = cloud->header.stamp;
  sup_->onPoints(points_, cloud, cloud_stamp_.toSec());
  const ros::Time now = ros::Time::now();
  carryOut(sup_->step(now.toSec()), now);
  if (sup_->volumeResult().invalid_points > 0)
    NODELET_WARN_THROTTLE(10.0, "cloud has %u points with NaN/inf coordinates (ignored)",
                          sup_->volumeResult().invalid_points);
  display_->showCloud(*sup_, points_, cloud_stamp_);
  // After the stop decision: ray ends of this image that came first go into the map now.
  if (const auto in = sup_->pairPoints(cloud, cloud_stamp_.toSec()))
    insertRays(*in);
}

void ObstacleNodelet::onRays(const Cloud::ConstPtr& cloud)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (cloud->header.stamp.isZero())
  {
    NODELET_WARN_THROTTLE(2.0, "refusing a ray cloud without a stamp (header.stamp 0)");
    return;
  }
  for (const RayInsert& in : sup_->pairRays(cloud, cloud->header.stamp.toSec()))
    insertRays(in);
}

void ObstacleNodelet::insertRays(const RayInsert& insert)
{
  const auto rays = std::any_cast<Cloud::ConstPtr>(insert.rays);
  const auto points = insert.points ? std::any_cast<Cloud::ConstPtr>(*insert.points) : Cloud::ConstPtr();
  geometry_msgs::Transform to_odom;
  std::string e, points_error;
  if (!transformAt(*tf_buffer_, params_.odom_frame, rays->header, to_odom, e))
  {
    NODELET_WARN_THROTTLE(2.0, "dropping ray cloud: %s", e.c_str());
    return;
  }
  if (!(e = imageRays(*rays, points.get(), to_odom, rays_, points_error)).empty())
  {
    NODELET_ERROR_THROTTLE(2.0, "dropping ray cloud in frame '%s': %s", rays->header.frame_id.c_str(), e.c_str());
    return;
  }
  if (!points_error.empty())
    NODELET_WARN_THROTTLE(10.0, "points cloud adds no rays to the map: %s", points_error.c_str());
  map_stamp_ = rays->header.stamp;
  sup_->addRays(rays_, rays->header.stamp.toSec());
  const ros::Time now = ros::Time::now();
  carryOut(sup_->step(now.toSec(), true), now);  // the plan on the updated map (after the stop check)
}

void ObstacleNodelet::onHazards(const sl_msgs::Hazards& msg)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (sup_->onBumpers(msg.bump_left, msg.bump_right, ros::Time::now().toSec()))
    NODELET_WARN("bumper (%s%s): marked in the local map", msg.bump_left ? "left" : "",
                 msg.bump_right ? (msg.bump_left ? " and right" : "right") : "");
}

void ObstacleNodelet::onCommand(const geometry_msgs::Twist& twist, const ros::Time& stamp)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!std::isfinite(twist.linear.x) || !std::isfinite(twist.angular.z))
    NODELET_WARN_THROTTLE(2.0, "cmd_vel_in: refusing a command with NaN or inf (linear.x %g, angular.z %g): stopped",
                          twist.linear.x, twist.angular.z);
  const ros::Time now = ros::Time::now();
  carryOut(sup_->onCommand(Velocity{ twist.linear.x, twist.angular.z }, stamp.toSec(), now.toSec()), now);
}

void ObstacleNodelet::onGoalResult(unsigned id, GoalEnd end, const std::string& what)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const ros::Time now = ros::Time::now();
  carryOut(sup_->onGoalResult(id, end, what, now.toSec()), now);
}

void ObstacleNodelet::onTimer(const ros::TimerEvent& /*event*/)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const ros::Time now = ros::Time::now();
  carryOut(sup_->step(now.toSec()), now);
  display_->showMap(*sup_, now);
}

void ObstacleNodelet::carryOut(const Actions& actions, const ros::Time& now)
{
  link_->send(actions, *sup_, now, cloud_stamp_, map_stamp_);
}
}  // namespace sl_obstacle

PLUGINLIB_EXPORT_CLASS(sl_obstacle::ObstacleNodelet, nodelet::Nodelet)
