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
}  // namespace sl_obstacle
