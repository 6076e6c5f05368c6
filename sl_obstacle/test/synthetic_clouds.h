// Synthetic clouds for the sl_obstacle gtests: a ray caster that imitates the structured-light sensor
// (16 x 64 dots whose rays cover the 331 x 173 mm window at 675 mm) over a scene of axis-aligned boxes
// and the floor, plus helpers for hand-placed points.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sensor_model.h"
#include "sl_obstacle/point.h"

namespace sl_obstacle
{
namespace test
{
/// An axis-aligned box obstacle in platform_edge (m).
struct SceneBox
{
  double x0, x1, y0, y1, z0, z1;
};

/// A scene: boxes and, optionally, the floor (z = 0).
struct Scene
{
  std::vector<SceneBox> boxes;
  bool floor = true;

  /// A wall facing the robot at distance x, wide and tall.
  Scene& wall(double x, double thickness = 0.05)
  {
    boxes.push_back(SceneBox{ x, x + thickness, -5.0, 5.0, -0.1, 3.0 });
    return *this;
  }
  /// A wall covering only y in [y0, y1].
  Scene& wallPart(double x, double y0, double y1)
  {
    boxes.push_back(SceneBox{ x, x + 0.05, y0, y1, -0.1, 3.0 });
    return *this;
  }
  /// A vertical leg of square cross-section @p size centred at (x + size/2, y).
  Scene& leg(double x, double y, double size = 0.02)
  {
    boxes.push_back(SceneBox{ x, x + size, y - 0.5 * size, y + 0.5 * size, -0.1, 0.75 });
    return *this;
  }
};

/// Ray-box intersection (slab method). @return entry distance along the unit ray or +inf.
inline double hitBox(const double o[3], const double d[3], const SceneBox& b)
{
  const double lo[3] = { b.x0, b.y0, b.z0 };
  const double hi[3] = { b.x1, b.y1, b.z1 };
  double t0 = 0.0;
  double t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
  {
    if (std::fabs(d[k]) < 1e-12)
    {
      if (o[k] < lo[k] || o[k] > hi[k])
      {
        return std::numeric_limits<double>::infinity();
      }
      continue;
    }
    double a = (lo[k] - o[k]) / d[k];
    double c = (hi[k] - o[k]) / d[k];
    if (a > c)
    {
      std::swap(a, c);
    }
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1)
    {
      return std::numeric_limits<double>::infinity();
    }
  }
  return t0 > 0.0 ? t0 : std::numeric_limits<double>::infinity();
}

/// Casts every ray of @p sensor into @p scene. Rays that hit nothing give no point.
inline std::vector<Point> render(const Scene& scene, const SensorModel& sensor = SensorModel())
{
  std::vector<Point> out;
  const double o[3] = { sensor.origin_x, sensor.origin_y, sensor.origin_z };
  for (int r = 0; r < sensor.rows; ++r)
  {
    for (int c = 0; c < sensor.cols; ++c)
    {
      const double ty = -0.5 * sensor.width + sensor.width * (c + 0.5) / sensor.cols;
      const double tz = sensor.height * (r + 0.5) / sensor.rows;
      double d[3] = { sensor.focus_x - o[0], ty - o[1], tz - o[2] };
      const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double& v : d)
      {
        v /= n;
      }
      double best = sensor.max_distance;
      bool hit = false;
      for (const SceneBox& b : scene.boxes)
      {
        const double t = hitBox(o, d, b);
        if (t < best)
        {
          best = t;
          hit = true;
        }
      }
      if (scene.floor && d[2] < 0.0)
      {
        const double t = -o[2] / d[2];
        if (t < best)
        {
          best = t;
          hit = true;
        }
      }
      if (hit)
      {
        out.push_back(makePoint(static_cast<float>(o[0] + best * d[0]), static_cast<float>(o[1] + best * d[1]),
                                static_cast<float>(o[2] + best * d[2])));
      }
    }
  }
  return out;
}

/// A dense rectangular patch of points at x in the y-z rectangle, spaced dy, dz.
inline std::vector<Point> patch(double x, double y0, double y1, double z0, double z1, double dy = 0.005,
                                double dz = 0.011)
{
  std::vector<Point> out;
  for (double z = z0; z <= z1 + 1e-9; z += dz)
  {
    for (double y = y0; y <= y1 + 1e-9; y += dy)
    {
      out.push_back(makePoint(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)));
    }
  }
  return out;
}

/// Appends @p extra to @p cloud.
inline std::vector<Point> operator+(std::vector<Point> cloud, const std::vector<Point>& extra)
{
  cloud.insert(cloud.end(), extra.begin(), extra.end());
  return cloud;
}
}  // namespace test
}  // namespace sl_obstacle
