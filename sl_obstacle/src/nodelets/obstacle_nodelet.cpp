// The sl_obstacle/obstacle nodelet: ROS wrapper around the core (VolumeChecker, DecisionMaker,
// WorldModel, SafetyFilter).
//
// Subscribes `points` (through a tf2 message filter into ~target_frame) for the immediate stop
// check and, with ~use_map, `ray_ends` (through a filter into ~odom_frame) and `hazards` for the
// local map (WorldModel); decides at the robot's current odometry pose. Publishes `obstacle_status`,
// `markers` and `local_map`, commands the robot through the driver's `drive_distance` action
// (sl_msgs) and/or `cmd_vel`. With the map, commands on `cmd_vel_in` (`cmd_vel_in_stamped`) pass
// through the SafetyFilter: always in command_mode filter, otherwise for ~teleop_hold after each one
// (taking over from autonomy). All callbacks share one mutex; nothing blocks in onInit.
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <message_filters/subscriber.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <nav_msgs/OccupancyGrid.h>
#include <sl_msgs/DriveDistanceAction.h>
#include <sl_msgs/Hazards.h>
#include <std_msgs/Empty.h>
#include <tf2/utils.h>

#include "cloud_conversion.h"
#include "filter_output.h"
#include "goal_result.h"
#include "markers.h"
#include "status.h"
#include "params.h"
#include "sl_msgs/ObstacleStatus.h"
#include "sl_obstacle/cloud_pairing.h"
#include "sl_obstacle/decision_maker.h"
#include "sl_obstacle/safety_filter.h"
#include "sl_obstacle/teleop_arbiter.h"
#include "sl_obstacle/velocity_goal.h"
#include "sl_obstacle/volume_checker.h"
#include "sl_obstacle/world_model.h"

namespace sl_obstacle
{
class ObstacleNodelet : public nodelet::Nodelet
{
public:
  ObstacleNodelet() = default;
  ~ObstacleNodelet() override;

private:
  using Cloud = sensor_msgs::PointCloud2;
  using Client = actionlib::SimpleActionClient<sl_msgs::DriveDistanceAction>;

  void onInit() override;
  void onCloud(const Cloud::ConstPtr& cloud);
  void processCloud(const Cloud::ConstPtr& cloud);
  void onFilterFailure(const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason);
  void onRays(const Cloud::ConstPtr& cloud);
  /// Inserts the rays of one image into the map: @p rays (ray_ends) and, when not null, the decoded
  /// @p points of the same image (the rays that reached a surface).
  void insertRays(const Cloud::ConstPtr& rays, const Cloud::ConstPtr& points);
  void onHazards(const sl_msgs::Hazards& msg);
  void onCommand(const geometry_msgs::Twist& msg);
  void onStampedCommand(const geometry_msgs::TwistStamped& msg);
  /// A command from cmd_vel_in given at @p stamp: takes over from autonomy (teleop_hold), filters.
  void takeCommand(const geometry_msgs::Twist& twist, const ros::Time& stamp);
  /// True while cmd_vel_in commands the robot (always in filter mode); ends a takeover when due.
  bool teleopActive(const ros::Time& now);
  /// One safety-filter step on the latest cmd_vel_in command. Caller holds mutex_.
  void filterStep(const ros::Time& now);
  /// Keeps the accepted obstacle points of @p cloud (in ~target_frame) for the filter.
  void keepObstacles(const Cloud& cloud, const VolumeResult& result);
  /// Moves the kept obstacle points into the odom frame once tf has the cloud's stamp.
  void resolveObstacles(const ros::Time& now);
  /// Reads the robot's pose in the odom frame now; false (with localization_detail_) when unknown.
  bool updatePose(const ros::Time& now);
  void publishMap(const ros::Time& now);
  void onTimer(const ros::TimerEvent& event);
  void onReconfigure(ObstacleConfig& config, uint32_t level);

  /// Runs one decision step at @p now and carries it out. Caller holds mutex_.
  /// One decision step; @p map_updated: right after a map update (the candidate turns are swept again).
  void decide(const ros::Time& now, bool map_updated = false);
  void execute(const Decision& d, const ros::Time& now);
  MotionState motion() const;
  void sendGoal(double distance, double speed);
  void cancelGoal();
  void publishTwist(double linear, double angular);
  /// Publishes the status of decision @p d, or of the last filter step when @p d is null.
  void publishStatus(const Decision* d, const ros::Time& now);
  void publishMarkers(const ros::Time& stamp);

  std::recursive_mutex mutex_;
  NodeletParams params_;
  std::unique_ptr<VolumeChecker> checker_;
  std::unique_ptr<DecisionMaker> decider_;
  VelocityGoal velocity_goal_;
  std::vector<Point> points_;
  std::unique_ptr<WorldModel> world_;                 // null without ~use_map
  CloudPairing<Cloud::ConstPtr, ros::Time> pairing_;  // each image's ray ends with its points
  double cloud_contact_ = 0.0;                        // the latest cloud's obstacle: travel until the disc touches it
  std::vector<MapRay> rays_;
  Pose2D pose_;
  bool localized_ = false;
  const char* localization_detail_ = "no odometry yet";
  bool bumped_ = false;
  ros::Time map_published_;
  bool have_frame_ = false;
  ros::Time last_cloud_stamp_;
  ros::Time map_stamp_;  // stamp of the newest ray cloud in the map

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<message_filters::Subscriber<Cloud>> cloud_sub_;
  std::unique_ptr<tf2_ros::MessageFilter<Cloud>> tf_filter_;
  std::unique_ptr<message_filters::Subscriber<Cloud>> rays_sub_;
  std::unique_ptr<tf2_ros::MessageFilter<Cloud>> rays_filter_;
  ros::Subscriber hazards_sub_;
  ros::Publisher map_pub_;
  nav_msgs::OccupancyGrid grid_;
  ros::Publisher status_pub_;
  ros::Publisher markers_pub_;
  ros::Publisher cmd_vel_pub_;
  ros::Timer timer_;
  std::unique_ptr<dynamic_reconfigure::Server<ObstacleConfig>> reconfigure_;
  boost::recursive_mutex reconfigure_mutex_;
  ObstacleConfig config_;
  bool reconfigure_ready_ = false;

  std::unique_ptr<Client> client_;
  ros::Publisher heartbeat_pub_;  // drive_distance/heartbeat: the running goal's decisions go on
  bool goal_active_ = false;
  double goal_remaining_ = 0.0;
  double goal_speed_ = 0.0;
  unsigned goal_seq_ = 0;
  bool moving_ = false;  // the last twist published was non-zero

  ObstacleStatus status_;
  visualization_msgs::MarkerArray markers_;

  // Safety filter (with the map): the latest cmd_vel_in command and the cloud's obstacles.
  std::unique_ptr<SafetyFilter> filter_;
  ros::Subscriber command_sub_;
  ros::Subscriber stamped_command_sub_;
  geometry_msgs::Twist command_;
  ros::Time command_time_;
  bool have_command_ = false;
  TeleopArbiter teleop_;                // cmd_vel_in or autonomy
  std::vector<Point2> obstacles_edge_;  // the latest cloud's accepted obstacle points in ~target_frame
  ros::Time obstacles_stamp_;
  bool obstacles_pending_ = false;       // obstacles_edge_ not yet in odom (tf not there yet)
  std::vector<Point2> obstacles_odom_;   // the latest resolved cloud's obstacle points in odom
  std::vector<Point2> obstacles_robot_;  // ... in the robot's frame now
  FilterOutput filter_out_;
};

ObstacleNodelet::~ObstacleNodelet()
{
  // Stop callbacks before the members they use go away.
  timer_.stop();
  cloud_sub_.reset();
  tf_filter_.reset();
  rays_sub_.reset();
  rays_filter_.reset();
}

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
  config_ = params_.config;
  teleop_ = TeleopArbiter(params_.command_mode == CommandMode::FILTER);
  checker_ = std::make_unique<VolumeChecker>(params_.settings.checker);
  decider_ = std::make_unique<DecisionMaker>(params_.settings.decision);
  status_.header.frame_id = params_.target_frame;
  status_.sector_free_distance.resize(static_cast<std::size_t>(params_.settings.checker.sectors));

  status_pub_ = nh_.advertise<ObstacleStatus>("obstacle_status", 10);
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("markers", 1);
  cmd_vel_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel", 1);
  if (params_.command_mode == CommandMode::ACTION)
  {
    client_ = std::make_unique<Client>(nh_, "drive_distance", false);
    heartbeat_pub_ = ros::NodeHandle(nh_, "drive_distance").advertise<std_msgs::Empty>("heartbeat", 1);
  }

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh_);
  cloud_sub_ = std::make_unique<message_filters::Subscriber<Cloud>>();
  cloud_sub_->subscribe(nh_, "points", 2);
  cloud_sub_->registerCallback(&ObstacleNodelet::onCloud, this);
  tf_filter_ = std::make_unique<tf2_ros::MessageFilter<Cloud>>(*tf_buffer_, params_.target_frame, 5, nh_);
  tf_filter_->registerCallback(&ObstacleNodelet::processCloud, this);
  tf_filter_->registerFailureCallback([this](const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason)
                                      { onFilterFailure(cloud, reason); });

  if (params_.settings.world.enabled)
  {
    world_ = std::make_unique<WorldModel>(params_.settings.world);
    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("local_map", 1);
    hazards_sub_ = nh_.subscribe("hazards", 10, &ObstacleNodelet::onHazards, this);
    rays_sub_ = std::make_unique<message_filters::Subscriber<Cloud>>(nh_, "ray_ends", 2);
    rays_filter_ = std::make_unique<tf2_ros::MessageFilter<Cloud>>(*rays_sub_, *tf_buffer_, params_.odom_frame, 5, nh_);
    rays_filter_->registerCallback(&ObstacleNodelet::onRays, this);
    rays_filter_->registerFailureCallback([this](const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason)
                                          { onFilterFailure(cloud, reason); });
    filter_ = std::make_unique<SafetyFilter>(params_.settings.filter);
    command_sub_ = nh_.subscribe("cmd_vel_in", 1, &ObstacleNodelet::onCommand, this);
    stamped_command_sub_ = nh_.subscribe("cmd_vel_in_stamped", 1, &ObstacleNodelet::onStampedCommand, this);
  }

  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<ObstacleConfig>>(reconfigure_mutex_, pnh_);
  reconfigure_->setCallback([this](ObstacleConfig& config, uint32_t level) { onReconfigure(config, level); });
  reconfigure_ready_ = true;

  timer_ = nh_.createTimer(ros::Duration(1.0 / params_.control_rate), &ObstacleNodelet::onTimer, this);
  NODELET_INFO("obstacle: volume W %.3f x H %.3f x B %.3f m in %s, command_mode %s%s",
               params_.settings.checker.volume.width, params_.settings.checker.volume.height,
               params_.settings.checker.volume.depth, params_.target_frame.c_str(),
               params_.command_mode == CommandMode::ACTION    ? "action"
               : params_.command_mode == CommandMode::CMD_VEL ? "cmd_vel"
                                                              : "filter",
               filter_ ? ", cmd_vel_in filtered" : " (no map: cmd_vel_in ignored)");
}

void ObstacleNodelet::onReconfigure(ObstacleConfig& config, uint32_t /*level*/)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!reconfigure_ready_)
  {
    // The server's first call carries the start-up parameters, already checked by loadParams().
    config = config_;
    return;
  }
  std::string e;
  try
  {
    validateConfig(config);
  }
  catch (const std::invalid_argument& invalid)
  {
    e = invalid.what();
  }
  if (e.empty() && config.use_map != config_.use_map)
  {
    e = "use_map is read at start-up only";
  }
  if (!e.empty())
  {
    NODELET_ERROR("reconfigure refused, keeping the previous values: %s", e.c_str());
    config = config_;
    return;
  }
  const Settings settings = toSettings(config);
  checker_->setParams(settings.checker);
  decider_->setParams(settings.decision);
  if (world_ && changesWorld(config, config_))
  {
    world_ = std::make_unique<WorldModel>(settings.world);
    map_stamp_ = ros::Time();  // the new map holds no image yet
    NODELET_WARN("map parameters changed: the local map starts empty");
  }
  else if (world_)
  {
    world_->setClearance(settings.world.clearance);
  }
  if (filter_)
  {
    filter_ = std::make_unique<SafetyFilter>(settings.filter);
  }
  status_.sector_free_distance.resize(static_cast<std::size_t>(settings.checker.sectors));
  config_ = config;
  params_.config = config;
  params_.settings = settings;
  NODELET_INFO("reconfigured");
}

void ObstacleNodelet::onCloud(const Cloud::ConstPtr& cloud)
{
  if (cloud->header.stamp.isZero())
  {
    NODELET_WARN_THROTTLE(2.0, "refusing a cloud without a stamp (header.stamp 0): its age is unknown");
    return;
  }
  if (cloud->header.frame_id == params_.target_frame)
  {
    processCloud(cloud);  // already in the working-volume frame: no transform needed
  }
  else
  {
    tf_filter_->add(cloud);
  }
}

void ObstacleNodelet::onFilterFailure(const Cloud::ConstPtr& cloud, tf2_ros::FilterFailureReason reason)
{
  NODELET_WARN_THROTTLE(2.0, "dropping cloud in frame '%s' at %.3f: no transform to '%s' (%s)",
                        cloud->header.frame_id.c_str(), cloud->header.stamp.toSec(), params_.target_frame.c_str(),
                        reason == tf2_ros::filter_failure_reasons::OutTheBack     ? "older than the tf buffer"
                        : reason == tf2_ros::filter_failure_reasons::EmptyFrameID ? "empty frame_id"
                                                                                  : "transform unavailable");
}

void ObstacleNodelet::processCloud(const Cloud::ConstPtr& cloud)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  geometry_msgs::Transform transform;
  transform.rotation.w = 1.0;
  if (cloud->header.frame_id != params_.target_frame)
  {
    try
    {
      transform =
          tf_buffer_->lookupTransform(params_.target_frame, cloud->header.frame_id, cloud->header.stamp).transform;
    }
    catch (const tf2::TransformException& e)
    {
      NODELET_WARN_THROTTLE(2.0, "dropping cloud: %s", e.what());
      return;
    }
  }
  const std::string e = convertCloud(*cloud, transform, points_);
  if (!e.empty())
  {
    NODELET_ERROR_THROTTLE(2.0, "dropping cloud in frame '%s': %s", cloud->header.frame_id.c_str(), e.c_str());
    return;
  }
  if (have_frame_ && (cloud->header.stamp - last_cloud_stamp_).toSec() > params_.settings.decision.stale_timeout)
  {
    checker_->reset();  // after a gap the persistence history means nothing
  }
  have_frame_ = true;
  last_cloud_stamp_ = cloud->header.stamp;
  const VolumeResult& result = checker_->analyze(points_);
  cloud_contact_ = contactTravel(points_, result.obstacle_indices, params_.settings.world.footprint.radius);
  if (filter_)
  {
    keepObstacles(*cloud, result);
  }
  if (result.invalid_points > 0)
  {
    NODELET_WARN_THROTTLE(10.0, "cloud has %u points with NaN/inf coordinates (ignored)", result.invalid_points);
  }
  decide(ros::Time::now());
  if (markers_pub_.getNumSubscribers() > 0)
  {
    publishMarkers(cloud->header.stamp);
  }
  // After the stop decision: ray ends of this image that came first go into the map now.
  if (const auto in = pairing_.onPoints(cloud, cloud->header.stamp))
  {
    insertRays(in->rays, in->points.value_or(Cloud::ConstPtr()));
  }
}

void ObstacleNodelet::onRays(const Cloud::ConstPtr& cloud)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (cloud->header.stamp.isZero())
  {
    NODELET_WARN_THROTTLE(2.0, "refusing a ray cloud without a stamp (header.stamp 0)");
    return;
  }
  // The decoded points of the same image carry the rays that reached a surface. They come on
  // another topic and may arrive later (another connection, the points' own processing): then the
  // ray ends wait for them, one image at most.
  std::optional<Cloud::ConstPtr> older;
  const auto in = pairing_.onRays(cloud, cloud->header.stamp, older);
  if (older)
  {
    insertRays(*older, Cloud::ConstPtr());  // its points never came (gated, dropped)
  }
  if (in)
  {
    insertRays(in->rays, in->points.value_or(Cloud::ConstPtr()));
  }
}

void ObstacleNodelet::insertRays(const Cloud::ConstPtr& rays, const Cloud::ConstPtr& points)
{
  geometry_msgs::Transform to_odom;
  try
  {
    to_odom = tf_buffer_->lookupTransform(params_.odom_frame, rays->header.frame_id, rays->header.stamp).transform;
  }
  catch (const tf2::TransformException& e)
  {
    NODELET_WARN_THROTTLE(2.0, "dropping ray cloud: %s", e.what());
    return;
  }
  rays_.clear();
  std::string e = appendRays(*rays, to_odom, true, rays_);
  if (!e.empty())
  {
    NODELET_ERROR_THROTTLE(2.0, "dropping ray cloud in frame '%s': %s", rays->header.frame_id.c_str(), e.c_str());
    return;
  }
  if (points && points->header.frame_id == rays->header.frame_id &&
      !(e = appendRays(*points, to_odom, false, rays_)).empty())
  {
    NODELET_WARN_THROTTLE(10.0, "points cloud adds no rays to the map: %s", e.c_str());
  }
  world_->addRays(rays_, rays->header.stamp.toSec());
  map_stamp_ = rays->header.stamp;
  decide(ros::Time::now(), true);  // the plan on the updated map (the stop check on the cloud came first)
}

void ObstacleNodelet::onHazards(const sl_msgs::Hazards& msg)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const bool bump = msg.bump_left || msg.bump_right;
  if (bump && !bumped_ && localized_)
  {
    world_->markBump(pose_, msg.bump_left, msg.bump_right, ros::Time::now().toSec());
    NODELET_WARN("bumper (%s%s): marked in the local map", msg.bump_left ? "left" : "",
                 msg.bump_right ? (msg.bump_left ? " and right" : "right") : "");
  }
  bumped_ = bump;
}

bool ObstacleNodelet::updatePose(const ros::Time& now)
{
  geometry_msgs::TransformStamped t;
  try
  {
    t = tf_buffer_->lookupTransform(params_.odom_frame, params_.robot_frame, ros::Time(0));
  }
  catch (const tf2::TransformException&)
  {
    localization_detail_ = "no transform from ~odom_frame to ~robot_frame";
    return localized_ = false;
  }
  if ((now - t.header.stamp).toSec() > params_.settings.decision.stale_timeout)
  {
    localization_detail_ = "odometry transform older than stale_timeout";
    return localized_ = false;
  }
  pose_.x = t.transform.translation.x;
  pose_.y = t.transform.translation.y;
  pose_.yaw = tf2::getYaw(t.transform.rotation);
  return localized_ = true;
}

void ObstacleNodelet::keepObstacles(const Cloud& cloud, const VolumeResult& result)
{
  obstacles_edge_.clear();
  for (const std::uint32_t i : result.obstacle_indices)
  {
    obstacles_edge_.push_back(Point2{ points_[i].x, points_[i].y });
  }
  obstacles_stamp_ = cloud.header.stamp;
  obstacles_pending_ = true;
}

void ObstacleNodelet::resolveObstacles(const ros::Time& now)
{
  if (!obstacles_pending_)
  {
    return;
  }
  geometry_msgs::TransformStamped t;
  try
  {
    t = tf_buffer_->lookupTransform(params_.odom_frame, params_.target_frame, obstacles_stamp_);
  }
  catch (const tf2::TransformException& e)
  {
    // Odometry usually arrives a few ms after the image: keep the previous points until then.
    if ((now - obstacles_stamp_).toSec() > params_.settings.decision.stale_timeout)
    {
      NODELET_WARN_THROTTLE(5.0, "filter uses the map only: %s", e.what());
      obstacles_odom_.clear();
      obstacles_pending_ = false;
    }
    return;
  }
  Pose2D edge;  // ~target_frame in odom at the cloud's stamp
  edge.x = t.transform.translation.x;
  edge.y = t.transform.translation.y;
  edge.yaw = tf2::getYaw(t.transform.rotation);
  toParent(obstacles_edge_, edge, obstacles_odom_);
  obstacles_pending_ = false;
}

void ObstacleNodelet::onCommand(const geometry_msgs::Twist& msg)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  takeCommand(msg, ros::Time::now());
}

void ObstacleNodelet::onStampedCommand(const geometry_msgs::TwistStamped& msg)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (msg.header.stamp.isZero())
  {
    NODELET_WARN_THROTTLE(2.0, "refusing a cmd_vel_in_stamped command without a stamp (header.stamp 0)");
    return;
  }
  takeCommand(msg.twist, std::min(msg.header.stamp, ros::Time::now()));
}

void ObstacleNodelet::takeCommand(const geometry_msgs::Twist& twist, const ros::Time& stamp)
{
  const ros::Time now = ros::Time::now();
  if (!std::isfinite(twist.linear.x) || !std::isfinite(twist.angular.z))
  {
    NODELET_WARN_THROTTLE(2.0, "cmd_vel_in: refusing a command with NaN or inf (linear.x %g, angular.z %g): stopped",
                          twist.linear.x, twist.angular.z);
  }
  command_ = twist;
  command_time_ = stamp;
  have_command_ = true;
  if (teleop_.onCommand(now.toSec(), params_.settings.teleop_hold))
  {
    cancelGoal();
    velocity_goal_.stop();
    NODELET_INFO("cmd_vel_in takes over from autonomy (for %.1f s after the last command)",
                 params_.settings.teleop_hold);
  }
  decide(now);
}

bool ObstacleNodelet::teleopActive(const ros::Time& now)
{
  if (!filter_)
  {
    return false;
  }
  bool ended = false;
  const bool active = teleop_.update(now.toSec(), ended);
  if (ended)
  {
    decider_->reset();  // it plans anew from here: the robot moved under teleoperation
    if (moving_)
    {
      publishTwist(0.0, 0.0);
    }
    NODELET_INFO("cmd_vel_in quiet for %.1f s: autonomy resumes", params_.settings.teleop_hold);
  }
  return active;
}

void ObstacleNodelet::filterStep(const ros::Time& now)
{
  FilterInput in;
  in.now = now.toSec();
  in.command = Velocity{ command_.linear.x, command_.angular.z };
  in.command_time = have_command_ ? command_time_.toSec() : -std::numeric_limits<double>::infinity();
  in.localized = localized_;
  in.pose = pose_;
  in.cloud_time = have_frame_ ? last_cloud_stamp_.toSec() : -std::numeric_limits<double>::infinity();
  // The cloud's obstacles (static) seen from where the robot is now.
  resolveObstacles(now);
  toChild(obstacles_odom_, pose_, obstacles_robot_);
  in.obstacles = &obstacles_robot_;
  filter_out_ = filter_->filter(world_->map(), in);
  const Velocity& v = filter_out_.command;
  if (v.linear != 0.0 || v.angular != 0.0 || moving_)
  {
    publishTwist(v.linear, v.angular);
  }
  publishStatus(nullptr, now);
}

void ObstacleNodelet::publishMap(const ros::Time& now)
{
  if (map_pub_.getNumSubscribers() == 0 || (now - map_published_).toSec() < 0.5)
  {
    return;
  }
  map_published_ = now;
  int width = 0;
  double x0 = 0.0;
  double y0 = 0.0;
  world_->map().toOccupancy(now.toSec(), grid_.data, x0, y0, width);
  grid_.header.stamp = now;
  grid_.header.frame_id = params_.odom_frame;
  grid_.info.map_load_time = now;
  grid_.info.resolution = static_cast<float>(params_.settings.world.map.resolution);
  grid_.info.width = static_cast<uint32_t>(width);
  grid_.info.height = width > 0 ? static_cast<uint32_t>(grid_.data.size() / static_cast<std::size_t>(width)) : 0U;
  grid_.info.origin.position.x = x0;
  grid_.info.origin.position.y = y0;
  grid_.info.origin.orientation.w = 1.0;
  map_pub_.publish(grid_);
}

void ObstacleNodelet::onTimer(const ros::TimerEvent& /*event*/)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const ros::Time now = ros::Time::now();
  decide(now);
  if (world_ && localized_)
  {
    publishMap(now);
  }
}

MotionState ObstacleNodelet::motion() const
{
  MotionState m;
  if (params_.command_mode == CommandMode::ACTION)
  {
    m.driver_ready = client_ && client_->isServerConnected();
    m.driver_detail = "drive_distance action server not connected";
    m.goal_active = goal_active_;
    m.goal_remaining = goal_remaining_;
    m.goal_speed = goal_speed_;
  }
  else
  {
    m.driver_ready = cmd_vel_pub_.getNumSubscribers() > 0;
    m.driver_detail = "nobody subscribes cmd_vel";
    m.goal_active = velocity_goal_.active();
    m.goal_remaining = velocity_goal_.remaining();
    m.goal_speed = velocity_goal_.speed();
  }
  m.localized = localized_;
  m.localization_detail = localization_detail_;
  return m;
}

void ObstacleNodelet::decide(const ros::Time& now, bool map_updated)
{
  if (params_.command_mode == CommandMode::CMD_VEL && velocity_goal_.update(now.toSec()))
  {
    decider_->onGoalEnded(GoalEnd::REACHED, now.toSec(), "open-loop goal done");
  }
  if (world_ && updatePose(now))
  {
    world_->updatePose(pose_, now.toSec());
  }
  if (teleopActive(now))
  {
    filterStep(now);
    return;
  }
  if (have_frame_)
  {
    FrameSummary cloud = summarize(checker_->result(), last_cloud_stamp_.toSec());
    if (world_)
    {
      cloud.nearest_obstacle = cloud_contact_;  // the map keeps the clearance on the disc's travel
    }
    decider_->onFrame(world_ ? withMap(cloud, world_->summarize(pose_, now.toSec(), map_updated),
                                       3.0 * params_.settings.world.map.resolution)
                             : cloud);
  }
  const Decision& d = decider_->step(now.toSec(), motion());
  execute(d, now);
  if (goal_active_)
  {
    // Each decision step keeps the goal alive in the driver; a frozen or dead node stops the robot.
    heartbeat_pub_.publish(std_msgs::Empty());
  }
  publishStatus(&d, now);
}

void ObstacleNodelet::execute(const Decision& d, const ros::Time& now)
{
  switch (d.command)
  {
    case Command::NONE:
      if (params_.command_mode == CommandMode::CMD_VEL && velocity_goal_.active())
      {
        publishTwist(velocity_goal_.velocity(), 0.0);  // keeps the driver's watchdog fed
      }
      break;
    case Command::STOP:
      cancelGoal();
      velocity_goal_.stop();
      if (moving_)
      {
        publishTwist(0.0, 0.0);
      }
      break;
    case Command::DRIVE:
      if (params_.command_mode == CommandMode::ACTION)
      {
        if (moving_)
        {
          publishTwist(0.0, 0.0);  // end a turn before the goal takes over
        }
        sendGoal(d.distance, d.speed);
      }
      else
      {
        velocity_goal_.start(d.distance, d.speed, now.toSec());
        publishTwist(velocity_goal_.velocity(), 0.0);
      }
      break;
    case Command::TURN:
      cancelGoal();
      velocity_goal_.stop();
      publishTwist(0.0, d.angular_speed);
      break;
  }
}

void ObstacleNodelet::sendGoal(double distance, double speed)
{
  if (!client_)
  {
    return;
  }
  sl_msgs::DriveDistanceGoal goal;
  goal.distance = distance;
  goal.speed = speed;
  const unsigned seq = ++goal_seq_;
  goal_active_ = true;
  goal_remaining_ = distance;
  goal_speed_ = speed;
  client_->sendGoal(
      goal,
      [this, seq](const actionlib::SimpleClientGoalState& state, const sl_msgs::DriveDistanceResultConstPtr& r)
      {
        std::lock_guard<std::recursive_mutex> lock(mutex_);
        if (seq != goal_seq_ || !goal_active_)
        {
          return;  // a goal we replaced or cancelled ourselves
        }
        goal_active_ = false;
        std::string what;
        const GoalEnd end = goalEnd(r.get(), state.toString(), what);
        if (end == GoalEnd::FAILED)
        {
          NODELET_WARN_THROTTLE(5.0, "drive_distance goal failed (%s)", what.c_str());
        }
        const ros::Time now = ros::Time::now();
        decider_->onGoalEnded(end, now.toSec(), what);
        decide(now);
      },
      Client::SimpleActiveCallback(),
      [this, seq](const sl_msgs::DriveDistanceFeedbackConstPtr& feedback)
      {
        std::lock_guard<std::recursive_mutex> lock(mutex_);
        if (seq == goal_seq_ && goal_active_)
        {
          goal_remaining_ = feedback->distance_remaining;
        }
      });
}

void ObstacleNodelet::cancelGoal()
{
  if (!goal_active_)
  {
    return;
  }
  goal_active_ = false;
  ++goal_seq_;
  if (client_)
  {
    client_->cancelGoal();
  }
}

void ObstacleNodelet::publishTwist(double linear, double angular)
{
  geometry_msgs::Twist twist;
  twist.linear.x = linear;
  twist.angular.z = angular;
  cmd_vel_pub_.publish(twist);
  moving_ = linear != 0.0 || angular != 0.0;
}

void ObstacleNodelet::publishStatus(const Decision* d, const ros::Time& now)
{
  ObstacleStatus& s = status_;
  s.header.stamp = now;
  s.header.frame_id = params_.target_frame;
  if (have_frame_)
  {
    s.cloud_stamp = last_cloud_stamp_;
    s.data_age = (now - last_cloud_stamp_).toSec();
  }
  else
  {
    s.cloud_stamp = ros::Time();
    s.data_age = std::numeric_limits<double>::infinity();
  }
  s.map_stamp = map_stamp_;
  fillCloudStatus(checker_->result(), have_frame_, s);
  const FrameSummary& f = decider_->frame();
  const bool mapped = world_ && f.from_map;
  fillMapStatus(f, mapped, mapped ? world_->last().obstacle : 0.0, s);
  if (d != nullptr)
  {
    fillDecisionStatus(*d, s);
  }
  else
  {
    Velocity input{ command_.linear.x, command_.angular.z };
    fillFilterStatus(filter_out_, input, s);
  }
  status_pub_.publish(s);
}

void ObstacleNodelet::publishMarkers(const ros::Time& stamp)
{
  using visualization_msgs::Marker;
  const bool blocked =
      teleop_.active() ? filter_out_.reason == FilterReason::STOPPED_OBSTACLE : decider_->last().blocked;
  volumeMarkers(checker_->result(), params_.settings.checker.volume, points_, blocked, params_.target_frame, stamp,
                markers_);
  // The footprint the filtered command sweeps before it must stop (map frame).
  Marker& footprint = markers_.markers[5];
  footprint.ns = "footprint";
  footprint.header.frame_id = params_.odom_frame;
  footprint.header.stamp = ros::Time::now();
  footprint.action = teleop_.active() && localized_ ? Marker::ADD : Marker::DELETE;
  footprintMarker(filter_out_, pose_, params_.settings.filter.footprint.radius, footprint);
  deleteEmptyPointMarkers(markers_);
  markers_pub_.publish(markers_);
}
}  // namespace sl_obstacle

PLUGINLIB_EXPORT_CLASS(sl_obstacle::ObstacleNodelet, nodelet::Nodelet)
