// Simulation only: plays the user who moves the calibration plane. Listens to the distance the
// calibration nodelet asks for next and moves the simulated robot (tf world -> robot frame, the
// true pose the camera simulator renders from) so that the wall of the calibration scene is at that
// distance. Not for real robots.
#include <cmath>
#include <memory>
#include <mutex>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/Float64.h>
#include <tf2_ros/transform_broadcaster.h>

#include "sl_evaluation/calibration_simulation.h"
#include "sl_params/params.h"
#include "sl_rig/ros/rig_param.h"

namespace sl_evaluation
{

/**
 * Publishes tf `~world_frame` -> `~robot_frame` at `~rate` with the robot standing so that the
 * plane named "wall" of `~scene_file` is `distance` (topic, std_msgs/Float64, m) in front of it,
 * as the calibration defines distances (`~reference`). The robot frame is `~robot_radius` behind
 * platform_edge, as for the camera simulator.
 */
class CalibrationSimStage : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::string scene_file, reference = "camera";
    double rate = 20.0;
    try
    {
      rig_ = sl_projector::loadRigParam(pnh, "rig_file").rig;  // the simulator's rig
      if (!sl_params::readIfSet(pnh, "scene_file", scene_file) || scene_file.empty())
        throw std::invalid_argument("~scene_file: required (a scene with a plane named 'wall', e.g. calib_wall.yaml)");
      scene_ = sl_sim::loadScene(scene_file);
      sl_params::readIfSet(pnh, "reference", reference);
      options_.reference = sl_calibration::parseDistanceReference(reference);
      sl_params::readIfSet(pnh, "robot_radius", robot_radius_);
      if (!(robot_radius_ >= 0.0 && robot_radius_ < 2.0))
        throw std::invalid_argument("~robot_radius: must be in [0, 2) m");
      sl_params::readIfSet(pnh, "world_frame", world_frame_);
      sl_params::readIfSet(pnh, "robot_frame", robot_frame_);
      sl_params::readIfSet(pnh, "initial_distance", distance_);
      sl_params::readIfSet(pnh, "rate", rate);
      if (!(rate > 0.0 && rate <= 1000.0))
        throw std::invalid_argument("~rate: must be in (0, 1000] Hz");
      platformEdgeForDistance(rig_, scene_, distance_, options_);  // checks the scene
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }
    broadcaster_.reset(new tf2_ros::TransformBroadcaster());
    sub_ = nh.subscribe("distance", 1, &CalibrationSimStage::onDistance, this);
    timer_ = nh.createTimer(ros::Duration(1.0 / rate), &CalibrationSimStage::onTimer, this);
    NODELET_INFO("simulation stage: moving %s in %s so that the wall is at the distance on %s (now %.3f m)",
                 robot_frame_.c_str(), world_frame_.c_str(), sub_.getTopic().c_str(), distance_);
  }

  void onDistance(const std_msgs::Float64ConstPtr& msg)
  {
    if (!(msg->data > 0.0 && msg->data < 20.0))
    {
      NODELET_ERROR("distance %f is not in (0, 20) m; ignored", msg->data);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      distance_ = msg->data;
    }
    NODELET_INFO("simulation stage: the wall is now %.3f m away", msg->data);
    publish();
  }

  void onTimer(const ros::TimerEvent&) { publish(); }

  void publish()
  {
    double d;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      d = distance_;
    }
    const Eigen::Isometry3d edge = platformEdgeForDistance(rig_, scene_, d, options_);
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = world_frame_;
    t.child_frame_id = robot_frame_;
    t.transform.translation.x = edge.translation().x() - robot_radius_;
    t.transform.translation.y = edge.translation().y();
    t.transform.translation.z = edge.translation().z();
    t.transform.rotation.w = 1.0;
    broadcaster_->sendTransform(t);
  }

  sl_projector::Rig rig_;
  sl_sim::Scene scene_;
  sl_calibration::PlaneCalibrationOptions options_;
  double robot_radius_ = 0.1675;
  std::string world_frame_ = "world", robot_frame_ = "base_footprint_true";
  double distance_ = 0.7;
  std::mutex mutex_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> broadcaster_;
  ros::Subscriber sub_;
  ros::Timer timer_;
};

}  // namespace sl_evaluation

PLUGINLIB_EXPORT_CLASS(sl_evaluation::CalibrationSimStage, nodelet::Nodelet)
