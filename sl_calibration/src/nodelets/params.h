// Parameters of the sl_calibration/calibration nodelet: read, typed and range-checked in one place.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "sl_calibration/camera_calibration.h"
#include "sl_calibration/common.h"
#include "sl_calibration/plane_calibration.h"
#include "sl_rig/rig.h"

namespace sl_calibration
{
/// Every parameter of the calibration nodelet.
struct CalibrationParams
{
  std::string mode = "plane";
  std::string output_file;
  double epipolar_tolerance = kCalibrationEpipolarTolerance;
  double capture_timeout = 10.0;
  double settle_time = 0.5;
  int frames_per_capture = 3;
  bool auto_calibrate = true;
  // Plane calibration.
  std::vector<double> distances;
  PlaneCalibrationOptions plane;
  std::string residuals_file;
  // Full calibration.
  std::string board_size = "8x5";
  double square = 0.02;
  int min_poses = 3;
  std::string camera_info_file;
  std::string camera_info_output;

  sl_projector::Rig rig;
  Board board;
};

/// Reads every private parameter of @p pnh and the rig to start from.
/// @throws std::invalid_argument "~<name>: ..." naming the first invalid parameter.
CalibrationParams readParams(const ros::NodeHandle& pnh);
}  // namespace sl_calibration
