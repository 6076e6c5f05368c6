#pragma once
/// @file residual_plot.h
/// @brief Pictures of reprojection residuals over the camera image: per observed point a dot and an
/// arrow of its residual, magnified by a stated factor, with a title, a legend and a scale bar
/// (OpenCV drawing only; ROS-free).

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_calibration/common.h"
#include "sl_calibration/full_calibration.h"
#include "sl_calibration/plane_calibration.h"

namespace sl_calibration
{

/// @brief What the colour of a point tells.
enum class ResidualColouring
{
  ByView,      ///< its view (a palette of 10 colours, repeated), named in the legend
  ByMagnitude  ///< its residual's length, from blue (0) to red (the largest), with a colour bar
};

/// @brief What a residual plot shows and how large it is.
struct ResidualPlotOptions
{
  cv::Size image_size;                  ///< the image the pixels are in (camera image), px; required
  std::string title;                    ///< title; '\n' separates lines
  std::vector<std::string> view_names;  ///< legend entry of each view (ByView); empty: "view 1", "view 2", ...
  ResidualColouring colouring = ResidualColouring::ByView;
  /// Arrow length per residual length (an arrow of a 0.1 px residual at x50 spans 5 image px).
  /// 0: automatic, a 1-2-5 step that draws the 95th percentile about 30 picture px long.
  double magnification = 0.0;
  int width = 1000;  ///< picture width, px; the image area is scaled to fit

  /// @brief Checks the fields. @throws std::invalid_argument naming the field.
  void validate() const;
};

/// @brief Where things are in a drawn residual plot.
struct ResidualPlotLayout
{
  cv::Size size;                    ///< the picture, px
  cv::Rect image_area;              ///< the camera image's area in the picture
  double scale = 1.0;               ///< picture px per image px
  double magnification = 1.0;       ///< the factor used (the one printed in the legend)
  double scale_bar_residual = 0.0;  ///< residual length the scale bar stands for, px
  int scale_bar_length = 0;         ///< its length in the picture, px

  /// @brief The picture position of image pixel @p pixel (pixel centres at integers).
  cv::Point2d toPicture(const Eigen::Vector2d& pixel) const;
};

/// @brief Size statistics of a set of residuals.
struct ResidualStatistics
{
  size_t points = 0;  ///< residuals
  double rms = 0.0;   ///< root mean square of their lengths, px
  double max = 0.0;   ///< the largest length, px
};

/// @brief The statistics of @p residuals (all zero for none).
ResidualStatistics residualStatistics(const std::vector<ImageResidual>& residuals);

/**
 * @brief Draws @p residuals over the image area: per point a dot at its observed pixel and an arrow
 * of its residual times the magnification; above, the title and a line with RMS, max and the number
 * of points; below, the scale bar with the magnification ("residuals x50") and the colour legend.
 * @param[out] layout where the image area, the scale and the scale bar are (optional).
 * @return an 8-bit BGR picture options.width px wide.
 * @throws CalibrationError when @p residuals is empty or none is finite.
 * @throws std::invalid_argument for invalid options (naming the field).
 */
cv::Mat drawResidualPlot(const std::vector<ImageResidual>& residuals, const ResidualPlotOptions& options,
                         ResidualPlotLayout* layout = nullptr);

/// @brief True if @p path ends in ".png" (any case).
bool isPngPath(const std::string& path);

/**
 * @brief Draws the plot and writes it as PNG to @p path.
 * @throws CalibrationError naming @p path when the path does not end in .png, there is nothing to
 * plot, or the file cannot be written.
 */
void writeResidualPlot(const std::string& path, const std::vector<ImageResidual>& residuals,
                       const ResidualPlotOptions& options);

/**
 * @brief Writes the plane calibration's column residuals (PlaneCalibrationResult::columnResiduals),
 * coloured by distance, over a camera image of @p image_size. @throws CalibrationError naming @p path.
 */
void writePlaneResidualPlot(const std::string& path, const PlaneCalibrationResult& result, cv::Size image_size);

/**
 * @brief Writes the full calibration's camera reprojection residuals of the board corners
 * (FullCalibrationResult::camera_residuals), coloured by board view. @throws CalibrationError naming
 * @p path, also when there were no board views.
 */
void writeCameraResidualPlot(const std::string& path, const FullCalibrationResult& result);

}  // namespace sl_calibration
