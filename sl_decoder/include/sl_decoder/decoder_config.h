#pragma once
/// @file decoder_config.h
/// @brief Tunables of the decoder, with their defaults and validation (ROS-free).

#include <string>

namespace sl_decoder
{

/// @brief Which depth model turns a decoded primitive into a 3D point.
enum class DepthMode
{
  Triangulation,  ///< camera ray against the projector ray of the decoded primitive (full calibration)
  Rational,       ///< per-primitive depth = (a + b u) / (1 + c u) from plane calibration
  Linear          ///< per-primitive depth = a + b u (the prototype's model)
};

/// @brief Parses "triangulation", "rational" or "linear". @throws std::invalid_argument otherwise.
DepthMode parseDepthMode(const std::string& name);
/// @brief The name of a depth mode.
const char* depthModeName(DepthMode mode);

/**
 * @brief Every tunable of the decoding pipeline. Pixel sizes are camera pixels.
 */
struct DecoderConfig
{
  // Local thresholding: a pixel is foreground when it exceeds the mean of its window by the offset.
  int threshold_window = 15;      ///< side of the square mean window, px (odd, >= 3)
  double threshold_offset = 3.0;  ///< grey levels above the local mean
  // Blob filters (speckles, bands, saturated patches).
  int min_area = 12;          ///< px
  int max_area = 1500;        ///< px
  int min_width = 3;          ///< bounding box, px
  int min_height = 5;         ///< bounding box, px
  int max_width = 60;         ///< bounding box, px
  int max_height = 90;        ///< bounding box, px
  double max_aspect = 1.6;    ///< width / height above this is a band, not a primitive
  double min_fill = 0.35;     ///< area / bounding-box area
  double min_contrast = 6.0;  ///< peak minus local mean, grey levels
  // Shape identification.
  int template_width = 8;         ///< samples across a blob
  int template_height = 14;       ///< samples down a blob
  double template_sigma = 0.8;    ///< blur of the ideal templates, template samples
  double min_margin = 0.08;       ///< best minus second-best correlation to identify a shape
  double min_correlation = 0.35;  ///< best correlation to identify a shape
  // Neighbour windows, in units of the local pattern step (east step, south step).
  double neighbour_along_min = 0.55;  ///< nearest acceptable distance along the direction
  double neighbour_along_max = 1.5;   ///< farthest acceptable distance along the direction
  double neighbour_across = 0.4;      ///< acceptable offset across the direction
  double max_depth_step = 0.02;       ///< neighbours support each other only within this depth
                                      ///< difference, as a fraction of the depth
  double max_size_deviation = 0.15;   ///< blobs whose box differs more than this fraction from the
                                      ///< frame's median size (cut by an edge, merged) are not decoded
  // Geometry.
  double epipolar_tolerance = 2.0;  ///< max distance of a primitive from its epipolar curve, px
  double min_depth = 0.25;          ///< m, camera z
  double max_depth = 2.5;           ///< m, camera z
  double nominal_depth = 0.7;       ///< m, where the pattern step is measured for the neighbour windows
  // Acceptance.
  int min_support = 2;          ///< consistent neighbours a decoded primitive needs (1 if its candidate is unique)
  double min_confidence = 0.0;  ///< points below this confidence are not output
  DepthMode depth_mode = DepthMode::Triangulation;  ///< depth model
  /// Near range: split components merged by defocus and overexposure (raised thresholds, the
  /// pattern's pitch, saturated outlines; BlobDetector). false: the detection of the first
  /// release (nothing decoded nearer than about 0.40 m), for comparison.
  bool split_merged = true;
  /// Identify primitives by their words (C, N, W, S, E) confirmed by neighbouring words, with the
  /// rig's geometry only as a loose prior (epipolar_tolerance, depth range): for calibrating a
  /// roughly measured rig, whose epipolar curves can be off by tens of pixels.
  bool identify_by_words = false;

  /**
   * @brief Checks every field.
   * @throws std::invalid_argument whose message starts with the field name.
   */
  void validate() const;
};

}  // namespace sl_decoder
