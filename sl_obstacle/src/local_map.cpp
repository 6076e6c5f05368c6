#include "sl_obstacle/local_map.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "slab.h"
#include "validation.h"

namespace sl_obstacle
{
namespace
{
constexpr std::uint8_t kFlagHit = 1;
constexpr std::uint8_t kFlagFree = 2;
constexpr std::uint8_t kFlagSuspect = 4;
constexpr std::uint8_t kFlagSuspects = 8;   // two or more lit ends in the voxel in one batch
constexpr std::uint8_t kFlagNearFree = 16;  // crossed free within near_free of a ray's start only
constexpr std::size_t kNoVoxel = std::numeric_limits<std::size_t>::max();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxCellsPerSide = 4096;
constexpr std::size_t kMaxVoxels = std::size_t(1) << 25;
// Lattice indices are clamped to this so that window arithmetic never overflows an int.
constexpr double kMaxIndex = 1e9;
// A free ray lowers a cell that holds a few hits only if it passes within this fraction of a cell of
// the box around them: beside a thin object it says nothing, through the place of a stray point it
// erases it.
constexpr double kExtentMargin = 0.25;
// A cell that is occupied and got hits from 3 or more (cloud, height slice) pairs holds a surface
// seen again and again (a cluster of wrong decodings in one image is not). A free ray lowers it only
// through the box around its hits shrunk by kExtentInset on each side: a ray grazing a round object
// crosses the corners of the box of its seen face, never the middle (a box corner lies inside a
// cylinder of radius up to kExtentInset / (1 - 1/sqrt(2)), 17 mm in 2 cm cells; larger objects
// span several cells). Once it decays below occupied, the few-hits rule applies again, so that the
// place of an object that went away cannot stay unknown for good ...
constexpr std::uint8_t kConfirmedHits = 3;
constexpr double kExtentInset = 0.25;
// ... but never narrower than this fraction of a cell on each side of the box's middle: the decoded
// points are sub-millimetre exact, so a ray this close to the place of the hits passes where the
// object was, and a moved object must still be forgotten.
constexpr double kExtentTolerance = 0.05;

/// The range (cell fractions) a free ray must cross to lower a cell whose hits span [lo, hi]:
/// grown by kExtentMargin for a few hits, the middle for a confirmed surface (see above).
void passRange(double lo, double hi, bool confirmed, double& pass_lo, double& pass_hi)
{
  if (!confirmed)
  {
    pass_lo = lo - kExtentMargin;
    pass_hi = hi + kExtentMargin;
    return;
  }
  const double mid = 0.5 * (lo + hi);
  pass_lo = std::min(lo + kExtentInset, mid - kExtentTolerance);
  pass_hi = std::max(hi - kExtentInset, mid + kExtentTolerance);
}

/// "<name> must be in (lo, hi] (got v)" unless lo < v <= hi.
std::string openClosed(const char* name, double v, double lo, double hi)
{
  if (std::isfinite(v) && v > lo && v <= hi)
  {
    return std::string();
  }
  std::ostringstream rule;
  rule << "must be in (" << lo << ", " << hi << "]";
  return detail::complaint(name, rule.str().c_str(), v);
}

/// Non-negative remainder.
int wrap(int v, int n)
{
  const int r = v % n;
  return r < 0 ? r + n : r;
}

}  // namespace

void MapParams::validate() const
{
  using detail::fail;
  fail(openClosed("map_size", size, 0.0, 100.0));
  fail(openClosed("map_resolution", resolution, 0.005, 0.2));
  const double cells = std::round(size / resolution);
  if (cells < 2 || cells > kMaxCellsPerSide)
  {
    fail(detail::complaint("map_size", "must be 2 to 4096 cells of map_resolution", size));
  }
  if (slices < 1 || slices > 16)
  {
    fail(detail::complaint("map_slices", "must be in [1, 16]", slices));
  }
  if (static_cast<std::size_t>(cells * cells) * static_cast<std::size_t>(slices) > kMaxVoxels)
  {
    fail(detail::complaint("map_slices", "times the cells must not exceed 2^25 voxels", slices));
  }
  fail(detail::inRange("map_z_min", z_min, -10.0, 10.0));
  fail(detail::inRange("map_z_max", z_max, -10.0, 10.0));
  if (z_max <= z_min)
  {
    fail(detail::complaint("map_z_max", "must be above map_z_min", z_max));
  }
  fail(detail::positive("map_decay", decay));
  fail(openClosed("map_clamp", clamp, 0.0, 100.0));
  fail(openClosed("map_hit", hit, 0.0, clamp));
  fail(openClosed("map_miss", miss, 0.0, clamp));
  fail(detail::inRange("map_suspect", suspect, 0.0, clamp));
  fail(detail::inRange("map_near_free", near_free, 0.0, 2.0));
  if (!(occupied_threshold > 0.0 && occupied_threshold < clamp))
  {
    fail(detail::complaint("map_occupied_threshold", "must be in (0, map_clamp)", occupied_threshold));
  }
  if (!(free_threshold < 0.0 && free_threshold > -clamp))
  {
    fail(detail::complaint("map_free_threshold", "must be in (-map_clamp, 0)", free_threshold));
  }
}

LocalMap::LocalMap(const MapParams& p) : params_(p)
{
  params_.validate();
  n_ = static_cast<int>(std::round(params_.size / params_.resolution));
  slices_ = params_.slices;
  inv_res_ = 1.0 / params_.resolution;
  slice_height_ = (params_.z_max - params_.z_min) / slices_;
  const std::size_t cells = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
  const std::size_t voxels = cells * static_cast<std::size_t>(slices_);
  logodds_.assign(voxels, 0.0F);
  updated_.assign(cells, -kInf);
  extent_.assign(cells, LocalMap::kNoExtent);
  trail_.assign(cells, 0);
  flags_.assign(voxels, 0);
  touched_.assign(voxels, 0);
  recenter(0.0, 0.0);
}

int LocalMap::cellIndex(double v) const
{
  const double i = std::floor(v * inv_res_);
  return static_cast<int>(std::max(-kMaxIndex, std::min(kMaxIndex, i)));
}

std::size_t LocalMap::slot(int lx, int ly) const
{
  int rx = ring_x_ + lx;
  int ry = ring_y_ + ly;
  rx -= rx >= n_ ? n_ : 0;
  ry -= ry >= n_ ? n_ : 0;
  return static_cast<std::size_t>(ry) * static_cast<std::size_t>(n_) + static_cast<std::size_t>(rx);
}

int LocalMap::sliceOf(double z) const
{
  const int k = static_cast<int>((z - params_.z_min) / slice_height_);
  return std::max(0, std::min(slices_ - 1, k));
}

void LocalMap::clear()
{
  std::fill(logodds_.begin(), logodds_.end(), 0.0F);
  std::fill(updated_.begin(), updated_.end(), -kInf);
  std::fill(extent_.begin(), extent_.end(), LocalMap::kNoExtent);
  std::fill(trail_.begin(), trail_.end(), 0);
}

void LocalMap::clearColumn(int rx)
{
  for (int ry = 0; ry < n_; ++ry)
  {
    const std::size_t cell = static_cast<std::size_t>(ry) * n_ + rx;
    std::fill_n(logodds_.begin() + cell * slices_, slices_, 0.0F);
    updated_[cell] = -kInf;
    extent_[cell] = LocalMap::kNoExtent;
    trail_[cell] = 0;
  }
}

void LocalMap::clearRow(int ry)
{
  const std::size_t first = static_cast<std::size_t>(ry) * n_;
  std::fill_n(logodds_.begin() + first * slices_, static_cast<std::size_t>(n_) * slices_, 0.0F);
  std::fill_n(updated_.begin() + first, n_, -kInf);
  std::fill_n(extent_.begin() + first, n_, LocalMap::kNoExtent);
  std::fill_n(trail_.begin() + first, n_, 0);
}

void LocalMap::recenter(double x, double y)
{
  if (!std::isfinite(x) || !std::isfinite(y))
  {
    return;
  }
  const int nx = cellIndex(x) - n_ / 2;
  const int ny = cellIndex(y) - n_ / 2;
  const long dx = static_cast<long>(nx) - ox_;
  const long dy = static_cast<long>(ny) - oy_;
  if (std::labs(dx) >= n_ || std::labs(dy) >= n_)
  {
    clear();
  }
  else
  {
    // The global columns (rows) that leave are the ring slots the entering ones reuse.
    const int first_x = dx > 0 ? ox_ : ox_ + n_ + static_cast<int>(dx);
    for (long i = 0; i < std::labs(dx); ++i)
    {
      clearColumn(wrap(first_x + static_cast<int>(i), n_));
    }
    const int first_y = dy > 0 ? oy_ : oy_ + n_ + static_cast<int>(dy);
    for (long i = 0; i < std::labs(dy); ++i)
    {
      clearRow(wrap(first_y + static_cast<int>(i), n_));
    }
  }
  ox_ = nx;
  oy_ = ny;
  ring_x_ = wrap(ox_, n_);
  ring_y_ = wrap(oy_, n_);
}

void LocalMap::decayCell(std::size_t cell, double stamp)
{
  const double last = updated_[cell];
  if (!(stamp > last))
  {
    return;
  }
  if (last > -kInf)
  {
    const float f = static_cast<float>(std::exp(-(stamp - last) / params_.decay));
    float* l = &logodds_[cell * slices_];
    for (int k = 0; k < slices_; ++k)
    {
      l[k] *= f;
    }
  }
  updated_[cell] = stamp;
}

void LocalMap::touch(std::size_t v, std::uint8_t flag)
{
  if (flags_[v] == 0)
  {
    touched_[touched_count_++] = static_cast<std::uint32_t>(v);
  }
  flags_[v] |= flag;
}

void LocalMap::flagCrossed(std::size_t cell, double z0, double z1, std::size_t skip_voxel, bool near)
{
  const double lo = std::max(std::min(z0, z1), params_.z_min);
  const double hi = std::min(std::max(z0, z1), params_.z_max);
  if (lo > hi)
  {
    return;
  }
  const std::size_t base = cell * slices_;
  for (int k = sliceOf(lo), last = sliceOf(hi); k <= last; ++k)
  {
    if (base + k != skip_voxel)
    {
      touch(base + k, near ? kFlagNearFree : kFlagFree);
    }
  }
}

void LocalMap::growExtent(const MapRay& r)
{
  const long lx = static_cast<long>(cellIndex(r.ex)) - ox_;
  const long ly = static_cast<long>(cellIndex(r.ey)) - oy_;
  if (lx < 0 || lx >= n_ || ly < 0 || ly >= n_ || r.ez < params_.z_min || r.ez > params_.z_max)
  {
    return;
  }
  const auto fraction = [this](double v)
  {
    const double f = v * inv_res_ - std::floor(v * inv_res_);
    return static_cast<std::uint8_t>(std::max(0.0, std::min(255.0, std::round(f * 255.0))));
  };
  const std::uint8_t fx = fraction(r.ex);
  const std::uint8_t fy = fraction(r.ey);
  Extent& e = extent_[slot(static_cast<int>(lx), static_cast<int>(ly))];
  e = { std::min(e.x0, fx), std::min(e.y0, fy), std::max(e.x1, fx), std::max(e.y1, fy), e.hits };
}

bool LocalMap::passesHits(std::size_t cell, double fx, double fy, double dfx, double dfy, double dt) const
{
  const Extent& e = extent_[cell];
  if (e.x0 > e.x1)
  {
    return true;  // no hit in this cell: every ray through it counts
  }
  // The piece of the ray inside the cell, in cell units from its lower left corner, against the
  // range around (a few hits) or in the middle of (a confirmed surface) the box of the cell's hits.
  const bool confirmed = e.hits >= kConfirmedHits && slotState(cell, batch_stamp_, nullptr) == CellState::Occupied;
  double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;
  passRange(e.x0 / 255.0, e.x1 / 255.0, confirmed, x0, x1);
  passRange(e.y0 / 255.0, e.y1 / 255.0, confirmed, y0, y1);
  double t0 = 0.0, t1 = dt;
  return detail::clipSlab(fx, dfx, x0, x1, t0, t1) && detail::clipSlab(fy, dfy, y0, y1, t0, t1);
}

void LocalMap::traverse(const MapRay& r)
{
  const double res = params_.resolution;
  const double px = r.sx - ox_ * res;  // start in window coordinates
  const double py = r.sy - oy_ * res;
  const double dx = double(r.ex) - r.sx, dy = double(r.ey) - r.sy, dz = double(r.ez) - r.sz;
  const double extent = n_ * res;

  std::size_t end_voxel = kNoVoxel;
  const long elx = static_cast<long>(cellIndex(r.ex)) - ox_;
  const long ely = static_cast<long>(cellIndex(r.ey)) - oy_;
  if (elx >= 0 && elx < n_ && ely >= 0 && ely < n_ && r.ez >= params_.z_min && r.ez <= params_.z_max)
  {
    end_voxel = slot(static_cast<int>(elx), static_cast<int>(ely)) * slices_ + sliceOf(r.ez);
  }
  if (r.kind != RayKind::Free && end_voxel != kNoVoxel)
  {
    const bool again = r.kind == RayKind::Suspect && (flags_[end_voxel] & kFlagSuspect) != 0;
    touch(end_voxel, r.kind == RayKind::Hit ? kFlagHit : (again ? kFlagSuspects : kFlagSuspect));
  }
  const std::size_t skip = r.kind == RayKind::Free ? kNoVoxel : end_voxel;

  double t = 0.0, t1 = 1.0;
  if (!detail::clipSlab(r.sz, dz, params_.z_min, params_.z_max, t, t1) ||
      !detail::clipSlab(px, dx, 0.0, extent, t, t1) || !detail::clipSlab(py, dy, 0.0, extent, t, t1))
  {
    return;
  }
  int ix = std::max(0, std::min(n_ - 1, static_cast<int>(std::floor((px + t * dx) * inv_res_))));
  int iy = std::max(0, std::min(n_ - 1, static_cast<int>(std::floor((py + t * dy) * inv_res_))));
  const int step_x = dx > 0 ? 1 : -1;
  const int step_y = dy > 0 ? 1 : -1;
  double next_x = dx > 0 ? ((ix + 1) * res - px) / dx : dx < 0 ? (ix * res - px) / dx : kInf;
  double next_y = dy > 0 ? ((iy + 1) * res - py) / dy : dy < 0 ? (iy * res - py) / dy : kInf;
  const double delta_x = dx != 0 ? res / std::fabs(dx) : kInf;
  const double delta_y = dy != 0 ? res / std::fabs(dy) : kInf;
  const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double near_t = length > 0.0 ? params_.near_free / length : 0.0;  // ray parameter of near_free
  for (int guard = 0; guard <= 2 * n_ + 2; ++guard)
  {
    const double t_next = std::min(t1, std::min(next_x, next_y));
    const std::size_t cell = slot(ix, iy);
    if (passesHits(cell, (px + t * dx) * inv_res_ - ix, (py + t * dy) * inv_res_ - iy, dx * inv_res_, dy * inv_res_,
                   t_next - t))
    {
      flagCrossed(cell, r.sz + t * dz, r.sz + t_next * dz, skip, t_next < near_t);
    }
    if (t_next >= t1)
    {
      break;
    }
    if (next_x <= next_y)
    {
      ix += step_x;
      next_x += delta_x;
    }
    else
    {
      iy += step_y;
      next_y += delta_y;
    }
    if (ix < 0 || ix >= n_ || iy < 0 || iy >= n_)
    {
      break;
    }
    t = t_next;
  }
}

void LocalMap::applyBatch(double stamp)
{
  const float clamp = static_cast<float>(params_.clamp);
  const float hit = static_cast<float>(params_.hit);
  const float miss = static_cast<float>(params_.miss);
  const float suspect = static_cast<float>(params_.suspect);
  for (std::size_t i = 0; i < touched_count_; ++i)
  {
    const std::size_t v = touched_[i];
    decayCell(v / slices_, stamp);
    float& l = logodds_[v];
    const std::uint8_t f = flags_[v];
    // Occupied beats suspect beats free where two or more lit rays end in the voxel: an object that
    // is lit but not decoded (a thin dark leg near the camera) lights several rays at one place and
    // must not be erased by the rays that pass beside it through the same cell. A single lit end
    // loses against free rays: unexplained light that is someone else's gives each primitive of its
    // row a suspect at another depth, scattered where the free rays know better.
    if (f & kFlagHit)
    {
      // A decoded point lifts a slice seen free to unknown first: the free rays of clouds placed a
      // few centimetres off (odometry and timing while turning) clear the cells around a thin leg,
      // and its hits, spread over them by the same error, must still mark it in the next cloud.
      l = std::min(std::max(l, 0.0F) + hit, clamp);
      std::uint8_t& hits = extent_[v / slices_].hits;  // one per cloud and slice
      hits = hits < 255 ? hits + 1 : 255;
    }
    else if ((f & kFlagSuspects) || !(f & (kFlagFree | kFlagNearFree)))
    {
      l = std::min(l + suspect, clamp);
    }
    else if ((f & kFlagFree) || l <= 0.0F || extent_[v / slices_].hits < kConfirmedHits)
    {
      l = std::max(l - miss, -clamp);
    }
    // else: only rays still near their start crossed a slice of a surface decoded again and again
    // (a stray decoding has too few hits to be kept): it stays.
    flags_[v] = 0;
    forgetExtentIfEmpty(v / slices_);
  }
  touched_count_ = 0;
}

void LocalMap::forgetExtentIfEmpty(std::size_t cell)
{
  const float* l = &logodds_[cell * slices_];
  if (*std::max_element(l, l + slices_) <= 0.0F)
  {
    extent_[cell] = LocalMap::kNoExtent;
  }
}

void LocalMap::insert(const std::vector<MapRay>& rays, double stamp)
{
  invalid_rays_ = 0;
  batch_stamp_ = stamp;
  if (!std::isfinite(stamp))
  {
    invalid_rays_ = rays.size();
    return;
  }
  const auto finite = [](const MapRay& r)
  {
    return std::isfinite(r.sx) && std::isfinite(r.sy) && std::isfinite(r.sz) && std::isfinite(r.ex) &&
           std::isfinite(r.ey) && std::isfinite(r.ez);
  };
  // The hits first, so that every free ray of the cloud meets the same extents.
  for (const MapRay& r : rays)
  {
    if (r.kind == RayKind::Hit && finite(r))
    {
      growExtent(r);
    }
  }
  for (const MapRay& r : rays)
  {
    if (!finite(r))
    {
      ++invalid_rays_;
      continue;
    }
    traverse(r);
  }
  applyBatch(stamp);
}

void LocalMap::setDisc(double x, double y, double radius, double stamp, float value, bool keep_seen)
{
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(radius) || radius < 0.0 || !std::isfinite(stamp))
  {
    return;
  }
  const double res = params_.resolution;
  const int y_lo = std::max(oy_, cellIndex(y - radius));
  const int y_hi = std::min(oy_ + n_ - 1, cellIndex(y + radius));
  const int x_lo = std::max(ox_, cellIndex(x - radius));
  const int x_hi = std::min(ox_ + n_ - 1, cellIndex(x + radius));
  const double r2 = radius * radius;
  for (int iy = y_lo; iy <= y_hi; ++iy)
  {
    const double cy = (iy + 0.5) * res - y;
    for (int ix = x_lo; ix <= x_hi; ++ix)
    {
      const double cx = (ix + 0.5) * res - x;
      if (cx * cx + cy * cy > r2)
      {
        continue;
      }
      const std::size_t cell = slot(ix - ox_, iy - oy_);
      const float* l = &logodds_[cell * slices_];
      if (keep_seen && *std::max_element(l, l + slices_) > 0.0F)
      {
        continue;
      }
      std::fill_n(logodds_.begin() + cell * slices_, slices_, value);
      updated_[cell] = std::max(updated_[cell], stamp);
      extent_[cell] = value > 0.0F ? LocalMap::kFullExtent : LocalMap::kNoExtent;
    }
  }
}

void LocalMap::markFreeDisc(double x, double y, double radius, double stamp)
{
  setDisc(x, y, radius, stamp, -static_cast<float>(params_.clamp));
}

void LocalMap::markFreeDiscExceptSeen(double x, double y, double radius, double stamp)
{
  setDisc(x, y, radius, stamp, -static_cast<float>(params_.clamp), true);
}

void LocalMap::markOccupiedDisc(double x, double y, double radius, double stamp)
{
  setDisc(x, y, radius, stamp, static_cast<float>(params_.clamp));
}

void LocalMap::markTrail(double x0, double y0, double x1, double y1, double radius)
{
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1) || !std::isfinite(radius) ||
      radius < 0.0)
  {
    return;
  }
  const double res = params_.resolution;
  const double dx = x1 - x0;
  const double dy = y1 - y0;
  const double length2 = dx * dx + dy * dy;
  const double r2 = radius * radius;
  const int y_lo = std::max(oy_, cellIndex(std::min(y0, y1) - radius));
  const int y_hi = std::min(oy_ + n_ - 1, cellIndex(std::max(y0, y1) + radius));
  const int x_lo = std::max(ox_, cellIndex(std::min(x0, x1) - radius));
  const int x_hi = std::min(ox_ + n_ - 1, cellIndex(std::max(x0, x1) + radius));
  for (int iy = y_lo; iy <= y_hi; ++iy)
  {
    const double py = (iy + 0.5) * res - y0;
    for (int ix = x_lo; ix <= x_hi; ++ix)
    {
      const double px = (ix + 0.5) * res - x0;
      // Distance from the cell's centre to the nearest point of the segment.
      const double t = length2 > 0.0 ? std::max(0.0, std::min(1.0, (px * dx + py * dy) / length2)) : 0.0;
      const double ex = px - t * dx;
      const double ey = py - t * dy;
      if (ex * ex + ey * ey <= r2)
      {
        trail_[slot(ix - ox_, iy - oy_)] = 1;
      }
    }
  }
}

CellState LocalMap::slotState(std::size_t cell, double now, bool* suspect_out) const
{
  const float* l = &logodds_[cell * slices_];
  float top = l[0];
  for (int k = 1; k < slices_; ++k)
  {
    top = std::max(top, l[k]);
  }
  const double occ = params_.occupied_threshold;
  // Decay only shrinks |log-odds|: a value between the thresholds stays unknown.
  if (top <= occ && top >= params_.free_threshold && (suspect_out == nullptr || top < 0.5 * occ))
  {
    return CellState::Unknown;
  }
  const double dt = now - updated_[cell];
  const double decayed = dt > 0.0 ? top * std::exp(-dt / params_.decay) : top;
  if (decayed > occ)
  {
    return CellState::Occupied;
  }
  if (decayed < params_.free_threshold)
  {
    return CellState::Free;
  }
  if (suspect_out != nullptr)
  {
    *suspect_out = decayed >= 0.5 * occ;
  }
  return CellState::Unknown;
}

CellState LocalMap::cellState(int ix, int iy, double now) const
{
  const long lx = static_cast<long>(ix) - ox_;
  const long ly = static_cast<long>(iy) - oy_;
  if (lx < 0 || lx >= n_ || ly < 0 || ly >= n_)
  {
    return CellState::Unknown;
  }
  return slotState(slot(static_cast<int>(lx), static_cast<int>(ly)), now, nullptr);
}

CellInfo LocalMap::cellInfo(int ix, int iy, double now) const
{
  CellInfo info;
  const long lx = static_cast<long>(ix) - ox_;
  const long ly = static_cast<long>(iy) - oy_;
  if (lx < 0 || lx >= n_ || ly < 0 || ly >= n_)
  {
    return info;
  }
  const std::size_t cell = slot(static_cast<int>(lx), static_cast<int>(ly));
  info.state = slotState(cell, now, nullptr);
  const float* l = &logodds_[cell * slices_];
  info.evidence = *std::max_element(l, l + slices_) > 0.0F;  // decay never changes the sign
  info.trail = trail_[cell] != 0;
  return info;
}

CellState LocalMap::state(double x, double y, double now) const
{
  if (!std::isfinite(x) || !std::isfinite(y))
  {
    return CellState::Unknown;
  }
  return cellState(cellIndex(x), cellIndex(y), now);
}

void LocalMap::toOccupancy(double now, std::vector<std::int8_t>& data, double& origin_x, double& origin_y,
                           int& width) const
{
  width = n_;
  origin_x = ox_ * params_.resolution;
  origin_y = oy_ * params_.resolution;
  data.resize(static_cast<std::size_t>(n_) * n_);
  std::size_t i = 0;
  for (int ly = 0; ly < n_; ++ly)
  {
    for (int lx = 0; lx < n_; ++lx, ++i)
    {
      bool suspect = false;
      const std::size_t cell = slot(lx, ly);
      const CellState s = slotState(cell, now, &suspect);
      // Occupied by lit suspects alone (no decoded point): 50, as a suspect; the decisions and the
      // filter still treat the cell as occupied.
      const bool hit = extent_[cell].hits > 0;
      data[i] = s == CellState::Occupied ? (hit ? 100 : 50) : s == CellState::Free ? 0 : suspect ? 50 : -1;
    }
  }
}
}  // namespace sl_obstacle
