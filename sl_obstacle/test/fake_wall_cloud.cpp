// Test-only node: a fake structured-light sensor that sees a wall at a fixed world x.
//
// Every 1/~rate s it looks up the robot's true pose (tf ~world_frame -> ~robot_frame, from create_sim),
// casts the 16 x 64 rays of the pattern (they cover the W x H window at 675 mm in front of the robot)
// from a sensor origin on the robot, intersects them with the wall plane x = ~wall_x (world) and the
// floor, and publishes the hits as a PointCloud2 (x, y, z, confidence float32; row, col uint16) in
// ~frame_id (platform_edge, or base_link with platform_edge at x = ~edge_offset). So the wall comes
// closer as the robot drives; setting ~wall_x while running moves the wall. ~stray_points random
// points in the box are added to each cloud.
// Service ~set_enabled (std_srvs/SetBool) stops and restarts publishing (stale data).
#include <cmath>
#include <random>
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_srvs/SetBool.h>
#include <tf2/utils.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "sensor_model.h"

namespace
{
class FakeWallCloud
{
public:
  FakeWallCloud() : pnh_("~"), listener_(buffer_)
  {
    pnh_.param("wall_x", wall_x_, 1.0);
    pnh_.param("world_frame", world_frame_, std::string("world"));
    pnh_.param("robot_frame", robot_frame_, std::string("base_footprint_true"));
    pnh_.param("frame_id", frame_id_, std::string("base_link"));
    pnh_.param("edge_offset", edge_offset_, 0.1675);
    pnh_.param("rate", rate_, 10.0);
    pnh_.param("max_distance", max_distance_, 1.5);
    pnh_.param("stray_points", stray_points_, 0);
    pnh_.param("enabled", enabled_, true);
    if (!(rate_ > 0.0) || !(max_distance_ > 0.0) || stray_points_ < 0)
    {
      throw std::invalid_argument("fake_wall_cloud: rate and max_distance must be > 0, stray_points >= 0");
    }
    pub_ = nh_.advertise<sensor_msgs::PointCloud2>("points", 2);
    service_ = pnh_.advertiseService("set_enabled", &FakeWallCloud::setEnabled, this);
    timer_ = nh_.createTimer(ros::Duration(1.0 / rate_), &FakeWallCloud::onTimer, this);
  }

private:
  bool setEnabled(std_srvs::SetBool::Request& request, std_srvs::SetBool::Response& response)
  {
    enabled_ = request.data;
    response.success = true;
    response.message = enabled_ ? "publishing" : "stopped";
    ROS_INFO("fake_wall_cloud: %s", response.message.c_str());
    return true;
  }

  void onTimer(const ros::TimerEvent& /*event*/)
  {
    if (!enabled_)
    {
      return;
    }
    pnh_.getParamCached("wall_x", wall_x_);  // may be moved while running
    geometry_msgs::TransformStamped pose;
    try
    {
      pose = buffer_.lookupTransform(world_frame_, robot_frame_, ros::Time(0));
    }
    catch (const tf2::TransformException& e)
    {
      ROS_WARN_THROTTLE(2.0, "fake_wall_cloud: no robot pose yet: %s", e.what());
      return;
    }
    const double rx = pose.transform.translation.x;
    const double yaw = tf2::getYaw(pose.transform.rotation);
    const double c = std::cos(yaw);
    const double s = std::sin(yaw);

    // The pattern's rays in platform_edge (x forward, y left, z up; origin at the front edge).
    const sl_obstacle::test::SensorModel sensor;
    const int rows = sensor.rows;
    const int cols = sensor.cols;
    const double ox = sensor.origin_x;
    const double oz = sensor.origin_z;
    // World x of the sensor origin (the edge is edge_offset ahead of the robot's centre).
    const double owx = rx + c * (edge_offset_ + ox);

    sensor_msgs::PointCloud2 cloud;
    cloud.header.stamp = ros::Time::now();
    cloud.header.frame_id = frame_id_;
    sensor_msgs::PointCloud2Modifier modifier(cloud);
    modifier.setPointCloud2Fields(6, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                                  "z", 1, sensor_msgs::PointField::FLOAT32, "confidence", 1,
                                  sensor_msgs::PointField::FLOAT32, "row", 1, sensor_msgs::PointField::UINT16, "col", 1,
                                  sensor_msgs::PointField::UINT16);
    modifier.resize(static_cast<std::size_t>(rows * cols + stray_points_));
    sensor_msgs::PointCloud2Iterator<float> it_x(cloud, "x");
    sensor_msgs::PointCloud2Iterator<float> it_y(cloud, "y");
    sensor_msgs::PointCloud2Iterator<float> it_z(cloud, "z");
    sensor_msgs::PointCloud2Iterator<float> it_c(cloud, "confidence");
    sensor_msgs::PointCloud2Iterator<uint16_t> it_row(cloud, "row");
    sensor_msgs::PointCloud2Iterator<uint16_t> it_col(cloud, "col");
    const double shift = frame_id_ == "platform_edge" ? 0.0 : edge_offset_;
    std::size_t n = 0;
    auto emit = [&](double x, double y, double z, int row, int col)
    {
      *it_x = static_cast<float>(x + shift);
      *it_y = static_cast<float>(y);
      *it_z = static_cast<float>(z);
      *it_c = 1.0F;
      *it_row = static_cast<uint16_t>(row);
      *it_col = static_cast<uint16_t>(col);
      ++it_x, ++it_y, ++it_z, ++it_c, ++it_row, ++it_col;
      ++n;
    };
    for (int r = 0; r < rows; ++r)
    {
      for (int k = 0; k < cols; ++k)
      {
        double dx = sensor.focus_x - ox;
        double dy = -0.5 * sensor.width + sensor.width * (k + 0.5) / cols;
        double dz = sensor.height * (r + 0.5) / rows - oz;
        const double norm = std::sqrt(dx * dx + dy * dy + dz * dz);
        dx /= norm;
        dy /= norm;
        dz /= norm;
        double t = max_distance_;
        bool hit = false;
        const double dwx = c * dx - s * dy;  // world x component of the ray
        if (dwx > 1e-9)
        {
          const double tw = (wall_x_ - owx) / dwx;
          if (tw > 0.0 && tw < t)
          {
            t = tw;
            hit = true;
          }
        }
        if (dz < 0.0)
        {
          const double tf = -oz / dz;
          if (tf < t)
          {
            t = tf;
            hit = true;
          }
        }
        if (hit)
        {
          emit(ox + t * dx, t * dy, oz + t * dz, r, k);
        }
      }
    }
    std::uniform_real_distribution<double> ux(0.05, 0.7);
    std::uniform_real_distribution<double> uy(-0.15, 0.15);
    std::uniform_real_distribution<double> uz(0.03, 0.16);
    for (int i = 0; i < stray_points_; ++i)
    {
      emit(ux(rng_), uy(rng_), uz(rng_), 0, 0);
    }
    modifier.resize(n);
    pub_.publish(cloud);
  }

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  ros::Publisher pub_;
  ros::ServiceServer service_;
  ros::Timer timer_;
  std::mt19937 rng_{ 7 };
  double wall_x_ = 1.0;
  std::string world_frame_;
  std::string robot_frame_;
  std::string frame_id_;
  double edge_offset_ = 0.1675;
  double rate_ = 10.0;
  double max_distance_ = 1.5;
  int stray_points_ = 0;
  bool enabled_ = true;
};
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "fake_wall_cloud");
  try
  {
    FakeWallCloud node;
    ros::spin();
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("%s", e.what());
    return 1;
  }
  return 0;
}
