/// @file plane_view.h
/// @brief A cheap stand-in for the simulator in the decoder's fuzz targets: the rig's camera
/// looking at a plane lit by the rig's pattern. Nearest-pixel sampling and a slight blur are
/// enough for the decoder to detect, classify and decode primitives, so fuzzing starts from
/// frames that reach every stage instead of from noise.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "sl_rig/rig.h"

namespace sl_fuzz
{
/// The plane: camera depth on the optical axis, tilts (normal (tilt_x, tilt_y, -1)), and brightness.
struct PlaneView
{
  double depth = 0.7;        ///< m, where the plane crosses the camera axis
  double tilt_x = 0.0;       ///< normal x component (left-right slant)
  double tilt_y = 0.0;       ///< normal y component (floor-like slant)
  double gain = 180.0;       ///< DN of a lit pattern pixel at 0.7 m
  double background = 15.0;  ///< DN everywhere

  bool operator==(const PlaneView& o) const
  {
    return depth == o.depth && tilt_x == o.tilt_x && tilt_y == o.tilt_y && gain == o.gain && background == o.background;
  }
};

/// @brief Renders PlaneView images for one rig (camera rays are computed once). Built without
/// sanitizers and optimised (plane_view.cpp): it is the harness, not the code under test.
class PlaneRenderer
{
public:
  explicit PlaneRenderer(const sl_projector::Rig& rig);

  /// @brief Renders into @p image (CV_8UC1, camera size); @p pattern is the projector frame.
  void render(const cv::Mat& pattern, const PlaneView& view, cv::Mat& image) const;

private:
  sl_projector::Rig rig_;
  double to_projector_[12];   // 3 x 4, row-major: camera optical frame -> projector optical frame
  std::vector<double> rays_;  // (x, y) of each pixel's ray (x, y, 1), row-major
};
}  // namespace sl_fuzz
