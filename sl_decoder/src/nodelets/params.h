// Parameters of the sl_decoder/decoder nodelet: read, typed and range-checked in one place.
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "sl_decoder/DecoderParamsConfig.h"
#include "sl_decoder/decoder_config.h"
#include "sl_decoder/ray_classifier.h"

namespace sl_decoder
{
/// Node parameters besides the rig (sl_projector::loadRigParam()).
struct NodeParams
{
  std::string target_frame = "platform_edge";
  std::string camera_frame;  ///< empty: the image's frame_id
  double tf_timeout = 0.0;
  bool organized = false;
  int queue_size = 2;
  bool rays = false;  ///< classify the rays even when nobody subscribes ray_ends
  DecoderConfig decoder;
  RayConfig ray;
};

/// Copies the reconfigurable tunables (cfg/DecoderParams.cfg) into @p d: at start and on every
/// reconfiguration, so the table and the decoder cannot drift apart.
void applyTunables(const DecoderParamsConfig& c, DecoderConfig& d);

/// Reads every private parameter of @p pnh but the rig.
/// @throws std::invalid_argument "~<name> ..." naming the first invalid parameter.
NodeParams readParams(const ros::NodeHandle& pnh);
}  // namespace sl_decoder
