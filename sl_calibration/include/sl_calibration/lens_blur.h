#pragma once
/// @file lens_blur.h
/// @brief The camera lens's optics (focus distance, f-number) from the blur of checkerboard edges
/// at known depths: the thin-lens model of sl_rig's LensOptics fitted to measured edge widths
/// (ROS-free).

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_calibration/camera_calibration.h"
#include "sl_rig/rig.h"

namespace sl_calibration
{

/// @brief The blur of one board edge: where it is on the board and how wide it is in the image.
struct EdgeBlur
{
  cv::Point3f on_board;  ///< the edge's middle in the board frame (z = 0), m
  double sigma = 0.0;    ///< Gaussian sigma of the edge's profile across it, px
  double rms = 0.0;      ///< residual of the profile fit, relative to the edge's contrast
};

/**
 * @brief Measures the blur of every edge between two adjacent inner corners of a found board: the
 * image profile across the edge's middle (averaged over its middle 40 %) fitted with a blurred step
 * (a + b * Phi(s / sigma)). Edges whose profile does not fit a step are left out.
 * @param corners the board's inner corners in @p grey (OpenCV order, see Board::objectPoints()).
 */
std::vector<EdgeBlur> measureBoardEdgeBlur(const cv::Mat& grey, const Board& board,
                                           const std::vector<cv::Point2f>& corners);

/// @brief One blur measurement at a known depth.
struct BlurSample
{
  double depth = 0.0;  ///< depth along the camera axis, m
  double sigma = 0.0;  ///< Gaussian sigma, px
};

/// @brief @p edges at their depths, the board at @p board_pose (board frame in the camera frame).
std::vector<BlurSample> blurAtDepth(const std::vector<EdgeBlur>& edges, const sl_projector::RigidTransform& board_pose);

/// @brief The thin-lens fit of a lens to blur samples.
struct LensFit
{
  bool valid = false;                       ///< samples on both sides of the focus and a small residual
  sl_projector::LensOptics lens;            ///< focus distance and f-number fitted, the pixel pitch given
  double base_sigma = 0.0;                  ///< blur at focus (lens, pixel, sampling), px
  double rms = 0.0;                         ///< residual of the fit, px
  int samples = 0;                          ///< samples used
  double min_depth = 0.0, max_depth = 0.0;  ///< depth range of the samples, m
  std::string note;                         ///< why the fit is not valid, or empty

  /// @brief One line: the lens or why it was not estimated.
  std::string summary(const std::string& what) const;
};

/**
 * @brief Fits sigma^2 = base^2 + (D(depth) / 4)^2, D the thin-lens blur circle of
 * sl_projector::LensOptics::defocusDiameter (a disc of diameter D has the second moment of a Gaussian of
 * sigma D / 4), to @p samples: the focus distance (0.15 to 5 m) by a search, base^2 and the
 * aperture by least squares.
 *
 * Only samples on both sides of the focus distance fix it (the blur grows alike nearer and
 * farther): the fit is valid when at least 10 % of the samples (and 5) lie more than 5 % nearer and
 * as many more than 5 % farther, and the residual is below 0.25 px.
 * @param f_px the lens's focal length, px. @param pixel_pitch m.
 */
LensFit fitLensOptics(const std::vector<BlurSample>& samples, double f_px, double pixel_pitch);

}  // namespace sl_calibration
