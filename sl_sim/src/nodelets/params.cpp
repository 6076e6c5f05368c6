#include "params.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "sl_params/params.h"
#include "sl_rig/ros/rig_param.h"

namespace sl_sim
{
namespace
{
// The rig and the scene, loaded from their files.
void readFiles(const ros::NodeHandle& pnh, SimParams& p)
{
  // ~rig_file is the deprecated former name of ~calibration_file.
  sl_projector::RigParam rig = sl_projector::loadRigParam(pnh, "rig_file");
  p.rig_file = std::move(rig.file);
  p.rig = std::move(rig.rig);
  if (!sl_params::readIfSet(pnh, "scene_file", p.scene_file) || p.scene_file.empty())
    throw std::invalid_argument("~scene_file: required (a scene file, e.g. $(find sl_sim)/scenes/room.yaml)");
  try
  {
    p.scene = loadScene(p.scene_file);
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument(std::string("~scene_file: ") + e.what());
  }
}

// Every simulator setting, read as a parameter of its own name (defaults: @p s).
SimSettings readSimSettings(const ros::NodeHandle& pnh, SimSettings s)
{
  for (const SimSettingInfo& info : simSettingsInfo())
  {
    const double current = getSimSetting(s, info.name);
    double value = current;
    switch (info.kind)
    {
      case SimSettingInfo::Kind::Double:
        value = sl_params::read(pnh, info.name, current);
        break;
      case SimSettingInfo::Kind::Int:
        value = sl_params::read(pnh, info.name, static_cast<int>(current));
        break;
      case SimSettingInfo::Kind::Bool:
        value = sl_params::read(pnh, info.name, current != 0.0) ? 1.0 : 0.0;
        break;
    }
    setSimSetting(s, info.name, value);
  }
  return s;
}

// Runs a core type's validate(), naming the parameter as a private one.
template <typename T>
void validateParams(const T& value)
{
  try
  {
    value.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
}

// A rate in (0, 1000] Hz.
double readRate(const ros::NodeHandle& pnh, const std::string& name, double fallback)
{
  const double rate = sl_params::read(pnh, name, fallback);
  if (!std::isfinite(rate) || rate <= 0.0 || rate > 1000.0)
    throw std::invalid_argument("~" + name + ": must be in (0, 1000] Hz, got " + std::to_string(rate));
  return rate;
}
}  // namespace

SimParams readParams(const ros::NodeHandle& pnh)
{
  SimParams p;
  readFiles(pnh, p);
  p.rate = readRate(pnh, "rate", p.rate);
  p.collision_rate = readRate(pnh, "collision_rate", p.collision_rate);
  p.seed = sl_params::read(pnh, "seed", p.seed);
  if (p.seed < 0)
    throw std::invalid_argument("~seed: must be >= 0, got " + std::to_string(p.seed));
  p.publish_depth = sl_params::read(pnh, "publish_depth", p.publish_depth);
  p.use_tf = sl_params::read(pnh, "use_tf", p.use_tf);
  p.world_frame = sl_params::read(pnh, "world_frame", p.world_frame);
  p.robot_frame = sl_params::read(pnh, "robot_frame", p.robot_frame);
  p.base_frame = sl_params::read(pnh, "base_frame", p.base_frame);
  p.camera_frame = sl_params::read(pnh, "camera_frame", p.camera_frame);
  for (const std::string* f : { &p.world_frame, &p.robot_frame, &p.base_frame, &p.camera_frame })
    if (f->empty())
      throw std::invalid_argument("~world_frame, ~robot_frame, ~base_frame and ~camera_frame must not be empty");
  p.settings = readSimSettings(pnh, p.settings);
  validateParams(p.settings);
  p.contact.robot_radius = sl_params::read(pnh, "robot_radius", p.contact.robot_radius);
  p.contact.robot_height = sl_params::read(pnh, "robot_height", p.contact.robot_height);
  p.contact.contact_min_height = sl_params::read(pnh, "contact_min_height", p.contact.contact_min_height);
  validateParams(p.contact);
  return p;
}
}  // namespace sl_sim
