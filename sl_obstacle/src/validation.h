// Internal helpers for parameter validation messages (not installed).
#pragma once

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sl_obstacle
{
namespace detail
{
/// "<name> <rule> (got <value>)".
template <typename T>
std::string complaint(const char* name, const char* rule, T value)
{
  std::ostringstream s;
  s << name << ' ' << rule << " (got " << value << ')';
  return s.str();
}

/// Empty when value is finite and > 0.
inline std::string positive(const char* name, double value)
{
  return (std::isfinite(value) && value > 0.0) ? std::string() : complaint(name, "must be > 0", value);
}

/// Empty when value is finite and >= 0.
inline std::string nonNegative(const char* name, double value)
{
  return (std::isfinite(value) && value >= 0.0) ? std::string() : complaint(name, "must be >= 0", value);
}

/// Empty when lo <= value <= hi (and finite).
inline std::string inRange(const char* name, double value, double lo, double hi)
{
  if (std::isfinite(value) && value >= lo && value <= hi)
  {
    return std::string();
  }
  std::ostringstream rule;
  rule << "must be in [" << lo << ", " << hi << "]";
  return complaint(name, rule.str().c_str(), value);
}

/// Throws std::invalid_argument(message) unless message is empty.
inline void fail(const std::string& message)
{
  if (!message.empty())
  {
    throw std::invalid_argument(message);
  }
}

/// Throws std::invalid_argument("<name> <rule> (got <value>)").
template <typename T>
[[noreturn]] void refuse(const char* name, const char* rule, T value)
{
  throw std::invalid_argument(complaint(name, rule, value));
}

/// Throws unless lo <= value <= hi (and finite).
inline void requireInRange(const char* name, double value, double lo, double hi)
{
  fail(inRange(name, value, lo, hi));
}
}  // namespace detail
}  // namespace sl_obstacle
