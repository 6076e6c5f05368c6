#pragma once
/// @file camera_calibration.h
/// @brief Camera intrinsics and distortion from checkerboard images (OpenCV's calibrateCamera), the
/// board's pose in a view, and the camera_info YAML of ROS's camera_calibration (ROS-free).

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_calibration/common.h"
#include "sl_rig/rig.h"

namespace sl_calibration
{

/**
 * @brief A checkerboard: its inner corners (as ROS camera_calibration's --size and OpenCV's
 * patternSize) and square size. A board of 9 x 6 squares has 8 x 5 inner corners.
 */
struct Board
{
  int cols = 8;          ///< inner corners along a row
  int rows = 5;          ///< inner corners along a column
  double square = 0.02;  ///< square size, m

  /// @brief Corner positions on the board (z = 0), row by row, m (OpenCV's order).
  std::vector<cv::Point3f> objectPoints() const;
  /// @brief Checks the fields. @throws std::invalid_argument naming the field.
  void validate() const;
};

/// @brief Parses "COLSxROWS" (inner corners, e.g. "8x5"). @throws std::invalid_argument otherwise.
Board parseBoardSize(const std::string& text, double square);

/**
 * @brief Finds the inner corners of @p board in a grey image (OpenCV findChessboardCorners with
 * adaptive threshold and normalisation, then cornerSubPix).
 * @return false if the board was not found (no partial boards).
 */
bool findBoardCorners(const cv::Mat& grey, const Board& board, std::vector<cv::Point2f>& corners);

/// @brief Corners found in one board image.
struct BoardView
{
  std::string name;                  ///< image name, for messages and reports
  std::vector<cv::Point2f> corners;  ///< OpenCV order (see Board::objectPoints)
};

/// @brief Options of the camera calibration.
struct CameraCalibrationOptions
{
  bool fix_k3 = true;            ///< keep k3 = 0 (as ROS camera_calibration does by default)
  bool zero_tangential = false;  ///< keep p1 = p2 = 0
  int min_views = 3;             ///< fewer board views are refused
};

/// @brief Result of the camera calibration.
struct CameraCalibrationResult
{
  sl_projector::PinholeModel camera;                      ///< intrinsics and distortion
  double rms = 0.0;                                       ///< reprojection error over all corners, px (rms)
  std::vector<double> view_rms;                           ///< per view, px
  std::vector<sl_projector::RigidTransform> board_poses;  ///< board frame in the camera optical frame, per view
};

/**
 * @brief Calibrates the camera from the corners of @p views (OpenCV calibrateCamera).
 * @throws CalibrationError for fewer than options.min_views views or a failed calibration.
 */
CameraCalibrationResult calibrateCamera(const std::vector<BoardView>& views, const Board& board, cv::Size image_size,
                                        const CameraCalibrationOptions& options = CameraCalibrationOptions());

/**
 * @brief Pose of the board (board frame in the camera optical frame) from its corners with a
 * known camera (solvePnP, iterative).
 * @param[out] rms reprojection error of the pose, px (optional).
 * @throws CalibrationError if the pose cannot be computed.
 */
sl_projector::RigidTransform boardPose(const sl_projector::PinholeModel& camera, const Board& board,
                                       const std::vector<cv::Point2f>& corners, double* rms = nullptr);

/// @brief The board's plane (z = 0 of the board frame) in the camera frame.
CalibrationPlane planeOfBoard(const sl_projector::RigidTransform& board_in_camera);

/**
 * @brief Reads a camera_info YAML file as written by ROS camera_calibration (image_width,
 * image_height, camera_matrix, distortion_model plumb_bob, distortion_coefficients).
 * @throws CalibrationError naming the file and the key.
 */
sl_projector::PinholeModel loadCameraInfo(const std::string& path);

/// @brief camera_info YAML text of @p camera (the format above, readable by camera_calibration_parsers).
std::string cameraInfoYaml(const sl_projector::PinholeModel& camera, const std::string& camera_name = "camera");

/// @brief Writes cameraInfoYaml() to @p path. @throws CalibrationError if it cannot be written.
void saveCameraInfo(const sl_projector::PinholeModel& camera, const std::string& path,
                    const std::string& camera_name = "camera");

}  // namespace sl_calibration
