// The picture of an exploration run (explore_rostest's ~map_png): the occupancy grids the obstacle
// node published, merged into one map, with the robot's true path and the scene's outline on it.
// No ROS: plain arrays and the scene in, an OpenCV image out (map_picture_test.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <sl_sim/scene.h>

namespace sl_bringup_test
{
/// A point in the map's frame, m.
struct MapPoint
{
  double x = 0.0, y = 0.0;
};

/// An axis-aligned box in the map's frame, m; empty while min > max.
struct MapBox
{
  double min_x = 1.0, min_y = 1.0, max_x = 0.0, max_y = 0.0;
  bool empty() const { return min_x > max_x || min_y > max_y; }
  /// Grows the box to hold @p p.
  void add(const MapPoint& p);
};

/// The map's frame in the world (the local map's: the odometry's, which starts at the start pose).
struct MapFrame
{
  double x = 0.0, y = 0.0, yaw = 0.0;
  /// A point of the world in this frame.
  MapPoint fromWorld(double world_x, double world_y) const;
  /// A point of this frame in the world.
  MapPoint toWorld(const MapPoint& p) const;
};

/**
 * @brief The outline of what the robot could touch: where rows and columns of horizontal rays,
 *        @p step apart across @p box (in @p frame) at @p heights above the floor, meet the scene's
 *        objects (not the floor).
 * @return the points in @p frame
 */
std::vector<MapPoint> sceneOutline(const sl_sim::Scene& scene, const MapFrame& frame, const MapBox& box,
                                   const std::vector<double>& heights = { 0.05, 0.15 }, double step = 0.02);

/**
 * Occupancy grids merged into one map of the area explored: every grid has the resolution of the
 * first, with its origin on a multiple of it (a rolling window); a known cell of a newer grid
 * replaces what the map held, an unknown one (-1) keeps it, so the map remembers what the rolling
 * window forgot.
 */
class ExploredMap
{
public:
  /**
   * @brief Merges one grid, row-major from its lower left cell at (@p origin_x, @p origin_y).
   * @param cells width * height values: -1 unknown, 0 free .. 100 occupied
   * @throws std::invalid_argument naming what is wrong (size, resolution, origin off the cells)
   */
  void merge(double origin_x, double origin_y, double resolution, int width, int height,
             const std::vector<std::int8_t>& cells);
  /// The value of the cell holding (@p x, @p y): -1 where no grid has known it.
  std::int8_t at(double x, double y) const;
  /// Cell size, m (0 before the first grid).
  double resolution() const { return resolution_; }
  /// The box of the known cells (empty: none yet).
  MapBox knownBox() const;

private:
  void growTo(long x0, long y0, long x1, long y1);

  double resolution_ = 0.0;
  long cx0_ = 0, cy0_ = 0;  // cell index of cells_[0]
  long width_ = 0, height_ = 0;
  std::vector<std::int8_t> cells_;  // row-major, -1 unknown
};

/// What the picture shows besides the map. All points in the map's frame.
struct MapPictureContent
{
  std::vector<MapPoint> path;      ///< the robot's path, in order: a line from blue (start) to red (end)
  std::vector<MapPoint> outline;   ///< ground truth: points on the scene's objects, orange dots
  std::vector<std::string> title;  ///< lines above the map
  double pixels_per_metre = 0.0;   ///< 0: the larger side about 700 pixels
  double margin = 0.2;             ///< m around the map and the path
};

/// Where a point of the map's frame lands in the picture.
struct MapPictureLayout
{
  MapBox box;  ///< the area shown
  double pixels_per_metre = 0.0;
  int top = 0;             ///< rows above the map (the title)
  int cols = 0, rows = 0;  ///< pixels of the map (from column 0, row top)
  cv::Point pixel(const MapPoint& p) const;
};

/**
 * @brief Draws @p map (free light, occupied dark, unknown grey) with @p content: the path, its start
 *        (green disc) and end (red cross), the outline, a 1 m scale bar and the title.
 * @param layout if not null, receives where the map's points went
 * @return a BGR image
 */
cv::Mat drawMapPicture(const ExploredMap& map, const MapPictureContent& content, MapPictureLayout* layout = nullptr);

/// The box the picture shows: the known cells and the path, @p margin around them.
MapBox pictureBox(const ExploredMap& map, const std::vector<MapPoint>& path, double margin);

/// Writes @p image as a PNG (best compression). @throws std::runtime_error naming @p file.
void writePng(const cv::Mat& image, const std::string& file);
}  // namespace sl_bringup_test
