#include "markers.h"

#include <std_msgs/ColorRGBA.h>

#include "filter_output.h"

namespace sl_obstacle
{
namespace
{
std_msgs::ColorRGBA color(float r, float g, float b, float a)
{
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}
}  // namespace

void volumeMarkers(const VolumeResult& r, const WorkingVolume& v, const std::vector<Point>& points, bool blocked,
                   const std::string& frame, const ros::Time& stamp, visualization_msgs::MarkerArray& out)
{
  using visualization_msgs::Marker;
  out.markers.resize(6);
  for (Marker& m : out.markers)
  {
    m.header.frame_id = frame;
    m.header.stamp = stamp;
    m.action = Marker::ADD;
    m.pose.orientation.w = 1.0;
    m.id = 0;
    m.lifetime = ros::Duration(0.0);
    m.frame_locked = false;
  }

  // The box: 12 edges.
  Marker& box = out.markers[0];
  box.ns = "box";
  box.type = Marker::LINE_LIST;
  box.scale.x = 0.005;
  box.color = blocked ? color(1.0F, 0.2F, 0.1F, 1.0F) : color(0.1F, 0.9F, 0.2F, 1.0F);
  box.points.clear();
  const double x0 = 0.0;
  const double x1 = v.depth;
  const double y0 = -0.5 * v.width;
  const double y1 = 0.5 * v.width;
  const double z0 = v.floor_margin;
  const double z1 = v.height;
  const double xs[2] = { x0, x1 };
  const double ys[2] = { y0, y1 };
  const double zs[2] = { z0, z1 };
  for (int a = 0; a < 2; ++a)
  {
    for (int b = 0; b < 2; ++b)
    {
      box.points.push_back(point(x0, ys[a], zs[b]));
      box.points.push_back(point(x1, ys[a], zs[b]));
      box.points.push_back(point(xs[a], y0, zs[b]));
      box.points.push_back(point(xs[a], y1, zs[b]));
      box.points.push_back(point(xs[a], ys[b], z0));
      box.points.push_back(point(xs[a], ys[b], z1));
    }
  }

  // The nearest obstacle point.
  Marker& nearest = out.markers[1];
  nearest.ns = "nearest";
  nearest.type = Marker::SPHERE;
  nearest.scale.x = nearest.scale.y = nearest.scale.z = 0.03;
  nearest.color = color(1.0F, 0.0F, 1.0F, 1.0F);
  nearest.action = r.nearest_index >= 0 ? Marker::ADD : Marker::DELETE;
  nearest.pose.position = point(r.nearest_point.x, r.nearest_point.y, r.nearest_point.z);

  // Obstacle points (accepted) and in-box points rejected as noise.
  Marker& obstacles = out.markers[2];
  obstacles.ns = "obstacles";
  obstacles.type = Marker::POINTS;
  obstacles.scale.x = obstacles.scale.y = 0.008;
  obstacles.color = color(1.0F, 0.1F, 0.1F, 1.0F);
  obstacles.points.clear();
  for (const std::uint32_t i : r.obstacle_indices)
  {
    obstacles.points.push_back(point(points[i].x, points[i].y, points[i].z));
  }
  Marker& rejected = out.markers[3];
  rejected.ns = "rejected";
  rejected.type = Marker::POINTS;
  rejected.scale.x = rejected.scale.y = 0.008;
  rejected.color = color(1.0F, 0.9F, 0.1F, 1.0F);
  rejected.points.clear();
  std::size_t k = 0;
  for (const std::uint32_t i : r.in_box_indices)
  {
    // obstacle_indices is an ordered subsequence of in_box_indices.
    if (k < r.obstacle_indices.size() && r.obstacle_indices[k] == i)
    {
      ++k;
      continue;
    }
    rejected.points.push_back(point(points[i].x, points[i].y, points[i].z));
  }

  // Free distance per sector, drawn on the floor.
  Marker& free = out.markers[4];
  free.ns = "free";
  free.type = Marker::LINE_LIST;
  free.scale.x = 0.01;
  free.color = color(0.2F, 0.5F, 1.0F, 1.0F);
  free.points.clear();
  for (const SectorResult& s : r.sectors)
  {
    free.points.push_back(point(s.free_distance, s.y_min, 0.0));
    free.points.push_back(point(s.free_distance, s.y_max, 0.0));
  }
}

void deleteEmptyPointMarkers(visualization_msgs::MarkerArray& markers)
{
  using visualization_msgs::Marker;
  for (Marker& m : markers.markers)
  {
    if (m.type == Marker::POINTS && m.points.empty())
    {
      m.action = Marker::DELETE;
    }
  }
}

void obstacleMarkers(const Supervisor& sup, const std::vector<Point>& points, const Settings& settings,
                     const std::string& volume_frame, const std::string& map_frame, const ros::Time& stamp,
                     const ros::Time& now, visualization_msgs::MarkerArray& out)
{
  using visualization_msgs::Marker;
  volumeMarkers(sup.volumeResult(), settings.checker.volume, points, sup.blocked(), volume_frame, stamp, out);
  Marker& footprint = out.markers[5];
  footprint.ns = "footprint";
  footprint.header.frame_id = map_frame;
  footprint.header.stamp = now;
  footprint.action = sup.teleopActive() && sup.localized() ? Marker::ADD : Marker::DELETE;
  footprintMarker(sup.filterOutput(), sup.pose(), settings.filter.footprint.radius, footprint);
  deleteEmptyPointMarkers(out);
}

void localMapGrid(const LocalMap& map, double resolution, const std::string& frame, const ros::Time& now,
                  nav_msgs::OccupancyGrid& grid)
{
  int width = 0;
  double x0 = 0.0;
  double y0 = 0.0;
  map.toOccupancy(now.toSec(), grid.data, x0, y0, width);
  grid.header.stamp = now;
  grid.header.frame_id = frame;
  grid.info.map_load_time = now;
  grid.info.resolution = static_cast<float>(resolution);
  grid.info.width = static_cast<uint32_t>(width);
  grid.info.height = width > 0 ? static_cast<uint32_t>(grid.data.size() / static_cast<std::size_t>(width)) : 0U;
  grid.info.origin.position.x = x0;
  grid.info.origin.position.y = y0;
  grid.info.origin.orientation.w = 1.0;
}

Display::Display(ros::NodeHandle& nh, const NodeletParams& params, bool map)
  : params_(params), markers_pub_(nh.advertise<visualization_msgs::MarkerArray>("markers", 1))
{
  if (map)
  {
    map_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("local_map", 1);
  }
}

void Display::showCloud(const Supervisor& sup, const std::vector<Point>& points, const ros::Time& stamp)
{
  if (markers_pub_.getNumSubscribers() == 0)
  {
    return;
  }
  obstacleMarkers(sup, points, params_.settings, params_.target_frame, params_.odom_frame, stamp, ros::Time::now(),
                  markers_);
  markers_pub_.publish(markers_);
}

void Display::showMap(const Supervisor& sup, const ros::Time& now)
{
  // 10 ms of slack: a timer tick a little early must not push the map to the next tick.
  if (!sup.world() || !sup.localized() || map_pub_.getNumSubscribers() == 0 ||
      (now - map_published_).toSec() < 1.0 / params_.map_rate - 0.01)
  {
    return;
  }
  map_published_ = now;
  localMapGrid(sup.world()->map(), params_.settings.world.map.resolution, params_.odom_frame, now, grid_);
  map_pub_.publish(grid_);
}
}  // namespace sl_obstacle
