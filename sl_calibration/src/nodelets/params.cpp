#include "params.h"

#include <stdexcept>

#include "sl_calibration/residual_plot.h"
#include "sl_params/params.h"
#include "sl_rig/ros/rig_param.h"

namespace sl_calibration
{
namespace
{
/// The mode, the files and the capture settings.
void readCommon(const ros::NodeHandle& pnh, CalibrationParams& p)
{
  sl_params::readIfSet(pnh, "mode", p.mode);
  if (p.mode != "plane" && p.mode != "full")
    throw std::invalid_argument("~mode: must be 'plane' or 'full', got '" + p.mode + "'");
  p.rig = sl_projector::loadRigParam(pnh).rig;  // the rig to start from
  if (!sl_params::readIfSet(pnh, "output_file", p.output_file) || p.output_file.empty())
    throw std::invalid_argument("~output_file: required (where the calibrated rig file is written)");
  sl_params::readIfSet(pnh, "epipolar_tolerance", p.epipolar_tolerance);
  if (!(p.epipolar_tolerance > 0.0 && p.epipolar_tolerance <= 50.0))
    throw std::invalid_argument("~epipolar_tolerance: must be in (0, 50] px");
  sl_params::readIfSet(pnh, "capture_timeout", p.capture_timeout);
  if (!(p.capture_timeout > 0.0 && p.capture_timeout <= 600.0))
    throw std::invalid_argument("~capture_timeout: must be in (0, 600] s");
  sl_params::readIfSet(pnh, "settle_time", p.settle_time);
  if (!(p.settle_time >= 0.0 && p.settle_time <= 60.0))
    throw std::invalid_argument("~settle_time: must be in [0, 60] s");
  sl_params::readIfSet(pnh, "frames_per_capture", p.frames_per_capture);
  if (p.frames_per_capture < 1 || p.frames_per_capture > 100)
    throw std::invalid_argument("~frames_per_capture: must be 1..100");
  sl_params::readIfSet(pnh, "auto_calibrate", p.auto_calibrate);
}

/// Plane calibration: the distances, their definition and the fit's limits.
void readPlane(const ros::NodeHandle& pnh, CalibrationParams& p)
{
  sl_params::readIfSet(pnh, "distances", p.distances);
  for (double d : p.distances)
    if (!(d > 0.0 && d < 20.0))
      throw std::invalid_argument("~distances: every distance must be in (0, 20) m, got " + std::to_string(d));
  std::string reference = "camera", normal = "robot";
  sl_params::readIfSet(pnh, "reference", reference);
  sl_params::readIfSet(pnh, "normal", normal);
  sl_params::readIfSet(pnh, "min_distances", p.plane.min_distances);
  sl_params::readIfSet(pnh, "max_rms", p.plane.max_rational_rms);
  sl_params::readIfSet(pnh, "residuals_file", p.residuals_file);
  try
  {
    p.plane.reference = parseDistanceReference(reference);
    p.plane.normal = parsePlaneNormal(normal);
    p.plane.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~reference / ~normal / ~min_distances / ~max_rms: ") + e.what());
  }
}

/// Full calibration: the board, the poses and the camera files.
void readFull(const ros::NodeHandle& pnh, CalibrationParams& p)
{
  sl_params::readIfSet(pnh, "board_size", p.board_size);
  sl_params::readIfSet(pnh, "square", p.square);
  try
  {
    p.board = parseBoardSize(p.board_size, p.square);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~board_size / ~square: ") + e.what());
  }
  sl_params::readIfSet(pnh, "min_poses", p.min_poses);
  if (p.min_poses < 3)
    throw std::invalid_argument("~min_poses: must be >= 3");
  sl_params::readIfSet(pnh, "camera_info_file", p.camera_info_file);
  sl_params::readIfSet(pnh, "camera_info_output", p.camera_info_output);
  if (p.mode == "full" && !p.residuals_file.empty() && !isPngPath(p.residuals_file))
    throw std::invalid_argument("~residuals_file: in full mode a picture, the name must end in .png, got '" +
                                p.residuals_file + "'");
}
}  // namespace

CalibrationParams readParams(const ros::NodeHandle& pnh)
{
  CalibrationParams p;
  readCommon(pnh, p);
  readPlane(pnh, p);
  readFull(pnh, p);
  return p;
}
}  // namespace sl_calibration
