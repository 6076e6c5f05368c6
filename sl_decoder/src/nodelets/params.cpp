#include "params.h"

#include <cmath>
#include <stdexcept>

#include "sl_params/params.h"

namespace sl_decoder
{
namespace
{
/// The ray classifier's parameters (~rays, ~min_albedo, ...), checked by RayConfig::validate().
void readRayParams(const ros::NodeHandle& pnh, NodeParams& p)
{
  p.rays = sl_params::read(pnh, "rays", p.rays);
  RayConfig& r = p.ray;
  r.min_albedo = sl_params::read(pnh, "min_albedo", r.min_albedo);
  r.pattern_contrast_1m = sl_params::read(pnh, "pattern_contrast_1m", r.pattern_contrast_1m);
  r.light_fraction = sl_params::read(pnh, "light_fraction", r.light_fraction);
  r.noise_floor = sl_params::read(pnh, "noise_floor", r.noise_floor);
  r.max_range = sl_params::read(pnh, "ray_max_range", r.max_range);
  try
  {
    r.validate();
    if (r.max_range <= p.decoder.min_depth || r.max_range > p.decoder.max_depth)
      throw std::invalid_argument("max_range must be in (min_depth, max_depth] of the decoder");
  }
  catch (const std::invalid_argument& e)
  {
    const std::string what = e.what();
    // The classifier's max_range is the parameter ~ray_max_range.
    throw std::invalid_argument(what.rfind("max_range", 0) == 0 ? "~ray_" + what : "~" + what);
  }
}
}  // namespace

void applyTunables(const DecoderParamsConfig& c, DecoderConfig& d)
{
  d.threshold_window = c.threshold_window | 1;  // keep it odd
  d.threshold_offset = c.threshold_offset;
  d.min_area = c.min_area;
  d.max_area = c.max_area;
  d.max_aspect = c.max_aspect;
  d.min_fill = c.min_fill;
  d.min_contrast = c.min_contrast;
  d.min_margin = c.min_margin;
  d.min_correlation = c.min_correlation;
  d.neighbour_along_min = c.neighbour_along_min;
  d.neighbour_along_max = c.neighbour_along_max;
  d.neighbour_across = c.neighbour_across;
  d.epipolar_tolerance = c.epipolar_tolerance;
  d.min_support = c.min_support;
  d.min_confidence = c.min_confidence;
  d.split_merged = c.split_merged;
}

NodeParams readParams(const ros::NodeHandle& pnh)
{
  NodeParams p;
  p.target_frame = sl_params::read(pnh, "target_frame", p.target_frame);
  if (p.target_frame.empty())
    throw std::invalid_argument("~target_frame must not be empty");
  p.camera_frame = sl_params::read(pnh, "camera_frame", p.camera_frame);
  p.tf_timeout = sl_params::read(pnh, "tf_timeout", p.tf_timeout);
  if (!std::isfinite(p.tf_timeout) || p.tf_timeout < 0.0 || p.tf_timeout > 5.0)
    throw std::invalid_argument("~tf_timeout must be in [0, 5] s");
  p.organized = sl_params::read(pnh, "organized", p.organized);
  p.queue_size = sl_params::read(pnh, "queue_size", p.queue_size);
  if (p.queue_size < 1)
    throw std::invalid_argument("~queue_size must be >= 1");
  DecoderConfig& d = p.decoder;
  d.min_depth = sl_params::read(pnh, "min_depth", d.min_depth);
  d.max_depth = sl_params::read(pnh, "max_depth", d.max_depth);
  d.nominal_depth = sl_params::read(pnh, "nominal_depth", d.nominal_depth);
  // The tunables: cfg/DecoderParams.cfg is their one table (defaults, ranges, descriptions).
  DecoderParamsConfig tunables = DecoderParamsConfig::__getDefault__();
  sl_params::checkReconfigureTypes<DecoderParamsConfig>(pnh);
  ros::NodeHandle server(pnh);
  tunables.__fromServer__(server);
  applyTunables(tunables, d);
  d.depth_mode = parseDepthMode(sl_params::read(pnh, "depth_mode", std::string(depthModeName(d.depth_mode))));
  try
  {
    d.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  readRayParams(pnh, p);
  return p;
}
}  // namespace sl_decoder
