// Parameters of the sl_sim/sim_camera nodelet: read, typed and range-checked in one place.
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "sl_rig/rig.h"
#include "sl_sim/contact.h"
#include "sl_sim/scene.h"
#include "sl_sim/sim_settings.h"

namespace sl_sim
{
/// Everything the nodelet is configured with.
struct SimParams
{
  std::string rig_file;
  std::string scene_file;
  double rate = 10.0;
  double collision_rate = 20.0;
  int seed = 0;
  bool publish_depth = true;
  bool use_tf = true;
  std::string world_frame = "world";
  std::string robot_frame = "base_footprint_true";
  std::string base_frame = "base_link";
  std::string camera_frame = "camera_optical_frame";
  SimSettings settings;
  ContactSettings contact;
  sl_projector::Rig rig;
  Scene scene;
};

/// Reads every private parameter of @p pnh and loads the rig and scene files.
/// @throws std::invalid_argument "~<name>: ..." naming the first invalid parameter.
SimParams readParams(const ros::NodeHandle& pnh);
}  // namespace sl_sim
