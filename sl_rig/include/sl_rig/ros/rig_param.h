#pragma once
/// @file rig_param.h
/// @brief The rig file parameter of the nodelets that need the rig (ROS side, header-only; not part
/// of the ROS-free sl_rig_core). A consumer includes it from a nodelet and finds roscpp and
/// sl_params itself (both header dependencies only: nothing more to link than sl_rig_core).

#include <stdexcept>
#include <string>

#include <ros/node_handle.h>
#include <sl_params/params.h>

#include "sl_rig/rig.h"

namespace sl_projector
{
/// @brief The rig a nodelet runs with, and the file it came from.
struct RigParam
{
  std::string file;  ///< the value of ~calibration_file (or of its deprecated former name)
  Rig rig;           ///< the rig that file holds
};

/**
 * @brief Reads the required private parameter `calibration_file` of @p pnh and loads the rig file it
 * names.
 * @param deprecated_name a former name of the parameter still read (with a warning) when
 *        `calibration_file` is not set; empty: none.
 * @throws std::invalid_argument starting with "~calibration_file" when the parameter is missing,
 *         empty or not a string, or the file cannot be loaded (the message of RigFileError after it).
 */
inline RigParam loadRigParam(const ros::NodeHandle& pnh, const std::string& deprecated_name = std::string())
{
  RigParam p;
  const bool set = deprecated_name.empty()
                       ? sl_params::readIfSet(pnh, "calibration_file", p.file)
                       : sl_params::readIfSetRenamed(pnh, "calibration_file", deprecated_name, p.file);
  if (!set || p.file.empty())
    throw std::invalid_argument(
        "~calibration_file: required (the rig file, e.g. $(find sl_projector)/config/default_rig.yaml)");
  try
  {
    p.rig = loadRig(p.file);
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument(std::string("~calibration_file: ") + e.what());
  }
  return p;
}
}  // namespace sl_projector
