// Internal helpers for parameter validation messages (not installed).
#pragma once

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sl_navigation
{
namespace detail
{
/// Throws std::invalid_argument("<name> must be in [lo, hi] (got v)") unless lo <= v <= hi.
inline void requireRange(const char* name, double v, double lo, double hi)
{
  if (std::isfinite(v) && v >= lo && v <= hi)
  {
    return;
  }
  std::ostringstream s;
  s << name << " must be in [" << lo << ", " << hi << "] (got " << v << ')';
  throw std::invalid_argument(s.str());
}
}  // namespace detail
}  // namespace sl_navigation
