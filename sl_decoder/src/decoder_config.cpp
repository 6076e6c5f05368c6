#include "sl_decoder/decoder_config.h"

#include <cmath>
#include <stdexcept>

namespace sl_decoder
{

DepthMode parseDepthMode(const std::string& name)
{
  if (name == "triangulation")
    return DepthMode::Triangulation;
  if (name == "rational")
    return DepthMode::Rational;
  if (name == "linear")
    return DepthMode::Linear;
  throw std::invalid_argument("depth_mode must be triangulation, rational or linear, got '" + name + "'");
}

const char* depthModeName(DepthMode mode)
{
  switch (mode)
  {
    case DepthMode::Triangulation:
      return "triangulation";
    case DepthMode::Rational:
      return "rational";
    case DepthMode::Linear:
      return "linear";
  }
  return "?";
}

namespace
{
void check(bool ok, const char* field, const std::string& rule)
{
  if (!ok)
    throw std::invalid_argument(std::string(field) + " " + rule);
}
bool finite(double v)
{
  return std::isfinite(v);
}
}  // namespace

void DecoderConfig::validate() const
{
  check(threshold_window >= 3 && threshold_window % 2 == 1 && threshold_window <= 255, "threshold_window",
        "must be odd, 3..255");
  check(finite(threshold_offset) && threshold_offset >= 0.0 && threshold_offset < 255.0, "threshold_offset",
        "must be in [0, 255)");
  check(min_area >= 1, "min_area", "must be >= 1");
  check(max_area >= min_area, "max_area", "must be >= min_area");
  check(min_width >= 1, "min_width", "must be >= 1");
  check(min_height >= 1, "min_height", "must be >= 1");
  check(max_width >= min_width, "max_width", "must be >= min_width");
  check(max_height >= min_height, "max_height", "must be >= min_height");
  check(finite(max_aspect) && max_aspect > 0.0, "max_aspect", "must be > 0");
  check(finite(min_fill) && min_fill >= 0.0 && min_fill <= 1.0, "min_fill", "must be in [0, 1]");
  check(finite(min_contrast) && min_contrast >= 0.0, "min_contrast", "must be >= 0");
  check(template_width >= 3 && template_width <= 64, "template_width", "must be 3..64");
  check(template_height >= 3 && template_height <= 64, "template_height", "must be 3..64");
  check(finite(template_sigma) && template_sigma >= 0.0, "template_sigma", "must be >= 0");
  check(finite(min_margin) && min_margin >= 0.0 && min_margin <= 2.0, "min_margin", "must be in [0, 2]");
  check(finite(min_correlation) && min_correlation >= -1.0 && min_correlation <= 1.0, "min_correlation",
        "must be in [-1, 1]");
  check(finite(neighbour_along_min) && neighbour_along_min > 0.0, "neighbour_along_min", "must be > 0");
  check(finite(neighbour_along_max) && neighbour_along_max > neighbour_along_min, "neighbour_along_max",
        "must be > neighbour_along_min");
  check(finite(neighbour_across) && neighbour_across > 0.0 && neighbour_across < 1.0, "neighbour_across",
        "must be in (0, 1)");
  check(finite(max_depth_step) && max_depth_step > 0.0, "max_depth_step", "must be > 0");
  check(finite(max_size_deviation) && max_size_deviation > 0.0, "max_size_deviation", "must be > 0");
  check(finite(epipolar_tolerance) && epipolar_tolerance > 0.0, "epipolar_tolerance", "must be > 0");
  check(finite(min_depth) && min_depth > 0.0, "min_depth", "must be > 0");
  check(finite(max_depth) && max_depth > min_depth, "max_depth", "must be > min_depth");
  check(finite(nominal_depth) && nominal_depth >= min_depth && nominal_depth <= max_depth, "nominal_depth",
        "must be within [min_depth, max_depth]");
  check(min_support >= 1 && min_support <= 4, "min_support", "must be 1..4");
  check(finite(min_confidence) && min_confidence >= 0.0 && min_confidence <= 1.0, "min_confidence",
        "must be in [0, 1]");
}

}  // namespace sl_decoder
