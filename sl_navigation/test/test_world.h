// A small synthetic world for the navigation tests: a truth grid of walls and posts, a camera-like
// sensor that fills a local window (free, occupied, unknown) from a pose, and a kinematic robot.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "sl_navigation/nav_grid.h"
#include "sl_navigation/path_follower.h"

namespace sl_navigation_test
{
using sl_navigation::OccupancyView;
using sl_navigation::Pose;

/// Truth: occupied cells of 0.02 m in a square of `size` m centred on the origin.
class World
{
public:
  explicit World(double size = 12.0, double res = 0.02) : res_(res), n_(static_cast<int>(size / res)), cells_(n_ * n_, 0)
  {
  }
  /// An axis-aligned solid box [x0, x1] x [y0, y1].
  void box(double x0, double y0, double x1, double y1)
  {
    for (int iy = index(y0); iy <= index(y1); ++iy)
    {
      for (int ix = index(x0); ix <= index(x1); ++ix)
      {
        if (inside(ix, iy))
        {
          cells_[iy * n_ + ix] = 1;
        }
      }
    }
  }
  /// A round post of radius r at (x, y).
  void post(double x, double y, double r)
  {
    for (int iy = index(y - r); iy <= index(y + r); ++iy)
    {
      for (int ix = index(x - r); ix <= index(x + r); ++ix)
      {
        if (inside(ix, iy) && std::hypot(center(ix) - x, center(iy) - y) <= r)
        {
          cells_[iy * n_ + ix] = 1;
        }
      }
    }
  }
  bool occupied(double x, double y) const
  {
    const int ix = index(x);
    const int iy = index(y);
    return !inside(ix, iy) || cells_[iy * n_ + ix] != 0;
  }
  /// Smallest distance from a disc of radius r at (x, y) to an occupied cell centre (negative: touching).
  double clearance(double x, double y, double r) const
  {
    double best = 1e9;
    const int reach = static_cast<int>((r + 0.5) / res_);
    for (int iy = index(y) - reach; iy <= index(y) + reach; ++iy)
    {
      for (int ix = index(x) - reach; ix <= index(x) + reach; ++ix)
      {
        if (!inside(ix, iy) || cells_[iy * n_ + ix])
        {
          best = std::min(best, std::hypot(center(ix) - x, center(iy) - y) - r);
        }
      }
    }
    return best;
  }

  /// A 4 x 4 m window at 0.02 m around the robot as a map of what a camera saw: cells within +-fov
  /// of the heading and between near and far, up to the first occupied cell along their ray, are
  /// written into @p memory (the whole world's cells, -1 where never seen); the robot's disc is free
  /// (its trail). The window is cut from the memory.
  void sense(const Pose& p, std::vector<std::int8_t>& memory, std::vector<std::int8_t>& data, OccupancyView& v,
             double fov = 0.45, double near = 0.3, double far = 1.5) const
  {
    const int w = 200;
    memory.resize(cells_.size(), -1);
    data.assign(w * w, -1);
    v.width = v.height = w;
    v.resolution = res_;
    v.origin_x = std::floor((p.x - 2.0) / res_) * res_;
    v.origin_y = std::floor((p.y - 2.0) / res_) * res_;
    // In view: within [near, far] and |bearing| <= fov, tested as cos(bearing) >= cos(fov) (fov < pi / 2):
    // no atan2 per cell, the loops run at 5 Hz over 40000 cells.
    const double cy = std::cos(p.yaw), sy = std::sin(p.yaw), cos_fov = std::cos(fov);
    for (int ly = 0; ly < w; ++ly)
    {
      for (int lx = 0; lx < w; ++lx)
      {
        const double x = v.origin_x + (lx + 0.5) * res_;
        const double y = v.origin_y + (ly + 0.5) * res_;
        const int ix = index(x);
        const int iy = index(y);
        if (!inside(ix, iy))
        {
          continue;
        }
        std::int8_t& m = memory[iy * n_ + ix];
        const double dx = x - p.x, dy = y - p.y;
        const double d = std::sqrt(dx * dx + dy * dy);
        if (d <= 0.16)
        {
          m = 0;
        }
        else if (d >= near && d <= far && dx * cy + dy * sy >= cos_fov * d)
        {
          const std::int8_t seen = visible(p, x, y, d);
          m = seen >= 0 ? seen : m;
        }
        data[ly * w + lx] = m;
      }
    }
    v.data = data.data();
  }

  /// Integrates (v, w) for dt.
  static void move(Pose& p, double v, double w, double dt)
  {
    p.x += v * std::cos(p.yaw + 0.5 * w * dt) * dt;
    p.y += v * std::sin(p.yaw + 0.5 * w * dt) * dt;
    p.yaw = std::remainder(p.yaw + w * dt, 2.0 * M_PI);
  }

private:
  std::int8_t visible(const Pose& p, double x, double y, double d) const
  {
    for (double t = 0.0; t < d - 0.5 * res_; t += 0.5 * res_)
    {
      if (occupied(p.x + (x - p.x) * t / d, p.y + (y - p.y) * t / d))
      {
        return -1;  // hidden behind something
      }
    }
    return occupied(x, y) ? 100 : 0;
  }
  int index(double v) const { return static_cast<int>(std::floor(v / res_)) + n_ / 2; }
  double center(int i) const { return (i - n_ / 2 + 0.5) * res_; }
  bool inside(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < n_ && iy < n_; }

  double res_;
  int n_;
  std::vector<std::uint8_t> cells_;
};
}  // namespace sl_navigation_test
