#pragma once
/// @file plot.h
/// @brief A small line chart drawn with OpenCV (ROS-free): panels stacked over one shared x axis, each
/// with its own y axis and series of (x, y) points, written as PNG; and the chart of `sl_eval --plot`.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_evaluation/evaluation.h"

namespace sl_evaluation
{

/// @brief One axis of a chart: its range, tick spacing and label.
struct ChartAxis
{
  std::string label;  ///< e.g. "distance (m)"
  double min = 0.0;   ///< value at the left or bottom edge of the plot area
  double max = 1.0;   ///< value at the right or top edge
  double tick = 0.0;  ///< spacing of the ticks and grid lines; 0: niceTick(min, max)
};

/// @brief A line through points (x, y) in one colour, with a marker on each point.
///
/// A point with a non-finite x or y is left out and breaks the line there; lines are clipped to the
/// plot area and markers outside it are not drawn.
struct ChartSeries
{
  std::string label;                ///< shown in the legend
  std::vector<cv::Point2d> points;  ///< in the order the line joins them
  cv::Scalar colour;                ///< BGR
};

/// @brief One plot area: its y axis and the series drawn on it.
struct ChartPanel
{
  ChartAxis y;                      ///< the panel's y axis
  std::vector<ChartSeries> series;  ///< drawn in this order; the legend lists them beside the panel
};

/// @brief A line chart: a title, the x axis all panels share, the panels from top to bottom.
struct Chart
{
  std::string title;               ///< above the panels
  ChartAxis x;                     ///< shared by the panels; its label under the bottom one
  std::vector<ChartPanel> panels;  ///< at least one
  int width = 900;                 ///< image width, px (at least 400)
  int height = 700;                ///< image height, px (every panel at least 60 px high)

  /**
   * @brief Checks sizes and axes.
   * @throws std::invalid_argument whose message starts with the field ("width", "x.max",
   * "panels[1].y.tick", ...): a non-finite or empty range, a negative tick or one giving more than 100
   * ticks, no panels, an image too small for its panels.
   */
  void validate() const;
};

/**
 * @brief A tick spacing of 1, 2 or 5 times a power of ten that gives about five ticks over [lo, hi].
 * @throws std::invalid_argument unless lo < hi, both finite.
 */
double niceTick(double lo, double hi);

/**
 * @brief An axis that holds every finite value of @p values, its ends on multiples of its tick.
 * @param from_zero start at 0 (or below, for negative values) instead of the smallest value
 * @return [0, 1] without finite values; a range around the value when all are equal.
 */
ChartAxis fitAxis(const std::string& label, const std::vector<double>& values, bool from_zero);

/// @brief The plot area of panel @p panel in the image, px (the frame is drawn on its border).
/// @throws std::invalid_argument for an invalid chart or panel index.
cv::Rect chartPlotArea(const Chart& chart, size_t panel);

/**
 * @brief The pixel (column, row) where data point (x, y) of panel @p panel is drawn, rounded; it lies
 * outside chartPlotArea() when the point is outside the axes' ranges.
 * @throws std::invalid_argument for an invalid chart or panel index.
 */
cv::Point chartPixel(const Chart& chart, size_t panel, double x, double y);

/**
 * @brief Draws the chart on a white 8-bit BGR image of width x height: title, grid, axes with tick
 * labels, series (lines, then a filled marker of radius 4 px centred on each point's chartPixel()),
 * and a legend to the right of each panel.
 * @throws std::invalid_argument for an invalid chart.
 */
cv::Mat renderChart(const Chart& chart);

/**
 * @brief Writes renderChart() to @p path as PNG.
 * @throws std::invalid_argument for an invalid chart or a path not ending in ".png";
 * std::runtime_error naming the file when it cannot be written.
 */
void writeChart(const Chart& chart, const std::string& path);

/**
 * @brief Checks, before a long run, that writeChart() can write @p path: it ends in ".png", its
 * directory exists and is writable, and it is neither a directory nor a read-only file. Creates nothing.
 * @throws std::invalid_argument for another suffix; std::runtime_error naming the file and the reason.
 */
void checkChartPath(const std::string& path);

/// @brief Decoding at one distance: one point of each series of decodingChart().
struct DistanceResult
{
  double distance = 0.0;  ///< m
  EvalStats stats;        ///< summed over the frames at that distance
};

/**
 * @brief The chart of `sl_eval --plot`: distance (m) on the x axis; on top the valid % of the visible
 * primitives (0 to 100), below the |depth error| (mm): mean, 95th percentile and max. Points in the
 * order of distance; a distance without ground-truth depth has no error points.
 */
Chart decodingChart(std::vector<DistanceResult> results, const std::string& title);

}  // namespace sl_evaluation
