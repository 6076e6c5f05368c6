#include "sl_navigation/coverage_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sl_navigation
{
CoverageGrid::CoverageGrid(const NavGrid& grid, double robot_radius) : radius_(robot_radius)
{
  if (!(robot_radius > 0.0 && robot_radius <= 1.0))
  {
    throw std::invalid_argument("robot_radius must be in (0, 1] m, got " + std::to_string(robot_radius));
  }
  reset(grid);
}

void CoverageGrid::reset(const NavGrid& grid)
{
  n_ = grid.width();
  resolution_ = grid.params().resolution;
  origin_x_ = grid.originX();
  origin_y_ = grid.originY();
  covered_.assign(static_cast<std::size_t>(n_) * n_, 0);
  covered_count_ = 0;
  has_last_ = false;
}

void CoverageGrid::markDisc(double x, double y)
{
  const int x0 = static_cast<int>(std::floor((x - radius_ - origin_x_) / resolution_));
  const int y0 = static_cast<int>(std::floor((y - radius_ - origin_y_) / resolution_));
  const int span = static_cast<int>(std::ceil(2.0 * radius_ / resolution_)) + 1;
  const double r2 = radius_ * radius_;
  for (int iy = std::max(0, y0); iy <= std::min(n_ - 1, y0 + span); ++iy)
  {
    const double dy = origin_y_ + (iy + 0.5) * resolution_ - y;
    for (int ix = std::max(0, x0); ix <= std::min(n_ - 1, x0 + span); ++ix)
    {
      const double dx = origin_x_ + (ix + 0.5) * resolution_ - x;
      std::uint8_t& c = covered_[index(ix, iy)];
      if (c == 0 && dx * dx + dy * dy <= r2)
      {
        c = 1;
        ++covered_count_;
      }
    }
  }
}

void CoverageGrid::markSegment(double x0, double y0, double x1, double y1)
{
  const double length = std::hypot(x1 - x0, y1 - y0);
  const int steps = std::min(100000, static_cast<int>(std::ceil(length / (0.5 * resolution_))));
  for (int k = 1; k <= steps; ++k)
  {
    const double t = static_cast<double>(k) / steps;
    markDisc(x0 + t * (x1 - x0), y0 + t * (y1 - y0));
  }
  markDisc(x0, y0);
}

void CoverageGrid::addPose(const Pose& pose)
{
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y))
  {
    has_last_ = false;
    return;
  }
  if (has_last_)
  {
    markSegment(last_.x, last_.y, pose.x, pose.y);
  }
  else
  {
    markDisc(pose.x, pose.y);
  }
  last_ = pose;
  has_last_ = true;
}

bool CoverageGrid::covered(int ix, int iy) const
{
  return ix >= 0 && iy >= 0 && ix < n_ && iy < n_ && covered_[index(ix, iy)] != 0;
}

double CoverageGrid::progress(const std::vector<FloorCell>& floor, std::size_t* covered_floor,
                              std::size_t* floor_cells) const
{
  std::size_t total = 0;
  std::size_t done = 0;
  const std::size_t n = std::min(floor.size(), covered_.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    if (floor[i] != FloorCell::None)
    {
      ++total;
      done += covered_[i];
    }
  }
  if (covered_floor)
  {
    *covered_floor = done;
  }
  if (floor_cells)
  {
    *floor_cells = total;
  }
  return total > 0 ? static_cast<double>(done) / total : 0.0;
}

void CoverageGrid::toOccupancy(const std::vector<FloorCell>& floor, std::vector<std::int8_t>& out) const
{
  out.assign(covered_.size(), -1);
  for (std::size_t i = 0; i < covered_.size(); ++i)
  {
    if (covered_[i])
    {
      out[i] = 100;
    }
    else if (i < floor.size() && floor[i] != FloorCell::None)
    {
      out[i] = 0;
    }
  }
}

void CoverageGrid::toRgb(const NavGrid& grid, double now, const std::vector<FloorCell>& floor,
                         std::vector<std::uint8_t>& out) const
{
  out.assign(covered_.size() * 3, 0);
  for (int iy = 0; iy < n_; ++iy)
  {
    for (int ix = 0; ix < n_; ++ix)
    {
      const std::size_t i = index(ix, iy);
      const Cell c = grid.cell(ix, iy, now);
      std::uint8_t rgb[3] = { 128, 128, 128 };  // unknown
      if (c == Cell::Occupied)
      {
        rgb[0] = rgb[1] = rgb[2] = 0;
      }
      else if (covered_[i])
      {
        rgb[0] = 70, rgb[1] = 130, rgb[2] = 230;
      }
      else if (i < floor.size() && floor[i] != FloorCell::None)
      {
        rgb[0] = 255, rgb[1] = 170, rgb[2] = 170;
      }
      else if (c == Cell::Free)
      {
        rgb[0] = rgb[1] = rgb[2] = 255;
      }
      const std::size_t o = (static_cast<std::size_t>(n_ - 1 - iy) * n_ + ix) * 3;  // north up
      std::copy(rgb, rgb + 3, out.begin() + o);
    }
  }
}

bool writePpm(const char* path, const std::vector<std::uint8_t>& rgb, int width, int height)
{
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
  {
    return false;
  }
  std::FILE* f = std::fopen(path, "wb");
  if (!f)
  {
    return false;
  }
  std::fprintf(f, "P6\n%d %d\n255\n", width, height);
  const bool ok = std::fwrite(rgb.data(), 1, rgb.size(), f) == rgb.size();
  return std::fclose(f) == 0 && ok;
}
}  // namespace sl_navigation
