// Clipping a line's parameter interval to a slab, shared by the map's ray traversal and the path
// checker's sweep (internal, not installed).
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

namespace sl_obstacle
{
namespace detail
{
/// Clips the parameter interval [t0, t1] of p0 + t * d to lo <= p <= hi. @return false if empty
/// (then t0 and t1 are left as they are when d is about 0, else t0 > t1).
inline bool clipSlab(double p0, double d, double lo, double hi, double& t0, double& t1)
{
  if (std::fabs(d) < 1e-12)
  {
    return p0 >= lo && p0 <= hi;
  }
  double ta = (lo - p0) / d;
  double tb = (hi - p0) / d;
  if (ta > tb)
  {
    std::swap(ta, tb);
  }
  t0 = std::max(t0, ta);
  t1 = std::min(t1, tb);
  return t0 <= t1;
}
}  // namespace detail
}  // namespace sl_obstacle
