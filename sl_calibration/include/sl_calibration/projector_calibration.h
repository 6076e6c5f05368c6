#pragma once
/// @file projector_calibration.h
/// @brief The projector as an inverse camera: intrinsics, distortion and pose relative to the camera
/// from decoded pattern primitives on calibration planes whose pose in the camera frame is known
/// (ROS-free).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "sl_calibration/common.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"

namespace sl_calibration
{

/// @brief One 3D-2D correspondence of the projector.
struct ProjectorCorrespondence
{
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      ///< on the calibration plane, camera optical frame, m
  Eigen::Vector2d projector = Eigen::Vector2d::Zero();  ///< the primitive's centroid, projector px
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();      ///< where the camera saw it, px
  int view = 0;                                         ///< index of the plane view
  int row = 0;                                          ///< pattern row
  int col = 0;                                          ///< pattern column
};

/**
 * @brief Correspondences of one plane view: the camera ray of each decoded primitive (through the
 * calibrated @p camera) meets @p plane at a 3D point whose projector pixel is the primitive's
 * centroid (Pattern::primitiveCentroid).
 */
std::vector<ProjectorCorrespondence> projectorCorrespondences(const sl_projector::Pattern& pattern,
                                                              const sl_projector::PinholeModel& camera,
                                                              const CalibrationPlane& plane,
                                                              const std::vector<PrimitiveSample>& samples, int view);

/// @brief Options of the projector calibration.
struct ProjectorCalibrationOptions
{
  int min_views = 3;             ///< distinct plane views needed
  int min_points_per_view = 30;  ///< a view with fewer decoded primitives is refused
  bool fix_k3 = true;            ///< keep k3 = 0
  bool zero_tangential = false;  ///< keep p1 = p2 = 0
  double outlier_px = 3.0;       ///< correspondences off by more than max(this, 4 x the median) are dropped, px
  double max_rms = 2.0;          ///< a larger final reprojection error is an error (wrong decodes or planes), px
  int max_iterations = 100;      ///< Levenberg-Marquardt iterations per pass
};

/// @brief Result of the projector calibration.
struct ProjectorCalibrationResult
{
  sl_projector::PinholeModel projector;  ///< intrinsics and distortion, frame-buffer px
  sl_projector::RigidTransform pose;     ///< projector optical frame in the camera optical frame
  double rms = 0.0;                      ///< reprojection error in the projector, px (inliers)
  std::vector<double> view_rms;          ///< per view, px (inliers)
  std::vector<int> view_points;          ///< inlier correspondences per view
  int points = 0;                        ///< inliers in all
  int outliers = 0;                      ///< dropped correspondences
  /// Per input correspondence: used in the final fit (false for outliers and views with too few points).
  std::vector<bool> inlier;
};

/**
 * @brief Calibrates the projector from 3D-2D correspondences in the camera frame.
 *
 * A linear estimate (normalised DLT of the 3 x 4 projection, decomposed into K, R, t; inside a
 * deterministic RANSAC so that wrong decodes do not bias it) starts a Levenberg-Marquardt
 * minimisation of the projector reprojection error over fx, fy, cx, cy, k1, k2, p1, p2 (k3), the
 * rotation and the translation; outliers (beyond max(outlier_px, 4 x the median residual)) are
 * then dropped and the fit repeated until the inlier set settles.
 * Points on planes with at least two distinct poses make the 3D points non-coplanar, which is all
 * the linear estimate needs; more poses at different orientations constrain it better.
 * @param width, height the projector frame size, px.
 * @throws CalibrationError for fewer than min_views views, too few points, a failed fit, or a final
 * reprojection error above max_rms.
 */
ProjectorCalibrationResult calibrateProjector(
    const std::vector<ProjectorCorrespondence>& correspondences, int width, int height,
    const ProjectorCalibrationOptions& options = ProjectorCalibrationOptions());

/**
 * @brief Reprojection residuals (projected - measured, projector px) of @p correspondences under a
 * projector model and pose.
 */
std::vector<Eigen::Vector2d> projectorResiduals(const std::vector<ProjectorCorrespondence>& correspondences,
                                                const sl_projector::PinholeModel& projector,
                                                const sl_projector::RigidTransform& pose);

}  // namespace sl_calibration
