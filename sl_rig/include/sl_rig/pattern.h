#pragma once
/// @file pattern.h
/// @brief The projected pattern: array, layout in the projector frame, rendering (ROS-free).

#include <string>

#include <opencv2/core.hpp>

#include "sl_rig/limits.h"
#include "sl_rig/pattern_array.h"
#include "sl_rig/word_table.h"

namespace sl_projector
{

/**
 * @brief Geometry of the pattern in the projector frame buffer.
 *
 * Cell (row, col) starts at (offset_x + col * cell_w, offset_y + row * cell_h) with
 * cell_w = primitive_width + gap_x and cell_h = primitive_height + gap_y; the primitive sits in
 * the cell with the gap split evenly around it (left/top get the smaller half). The defaults are
 * the prototype's: 16 x 64 primitives of 5 x 9 px with 2 px / 6 px gaps (7 x 15 px cells), top-left
 * aligned in a 480 x 320 frame.
 *
 * Limits (validate()): the frame is at most kMaxImageSide px a side; primitive sizes, gaps and
 * offsets are at most the frame's size, so cell sizes and positions always fit in int.
 */
struct PatternConfig
{
  int rows = 16;               ///< pattern rows
  int cols = 64;               ///< pattern columns
  int primitive_width = 5;     ///< primitive box width, projector px
  int primitive_height = 9;    ///< primitive box height, projector px
  int gap_x = 2;               ///< horizontal gap between primitives, projector px
  int gap_y = 6;               ///< vertical gap between primitives, projector px
  int offset_x = 0;            ///< left edge of the first cell, projector px
  int offset_y = 0;            ///< top edge of the first cell, projector px
  int projector_width = 480;   ///< frame width, px
  int projector_height = 320;  ///< frame height, px
  bool flip_x = false;         ///< mirror the frame left-right after layout (mounting)
  bool flip_y = false;         ///< mirror the frame top-bottom after layout (mounting)

  /// @brief Cell width, px (no overflow once validate() passed).
  int cellWidth() const { return primitive_width + gap_x; }
  /// @brief Cell height, px (no overflow once validate() passed).
  int cellHeight() const { return primitive_height + gap_y; }

  /**
   * @brief Checks every field.
   * @throws std::invalid_argument whose message starts with the offending field's name.
   */
  void validate() const;
};

/**
 * @brief The complete pattern: values, word table and geometry.
 *
 * Constructing it validates the configuration and the uniqueness of all interior words.
 */
class Pattern
{
public:
  /// @throws std::invalid_argument for an invalid configuration or non-unique words.
  explicit Pattern(const PatternConfig& config = PatternConfig());

  /// @brief The configuration.
  const PatternConfig& config() const { return config_; }
  /// @brief The value array.
  const PatternArray& array() const { return array_; }
  /// @brief The word table.
  const WordTable& words() const { return words_; }

  /**
   * @brief Projector pixel (x right, y down, pixel centres at integers) of the centroid of the
   * primitive at (row, col), in the displayed frame (flips applied).
   */
  cv::Point2d primitiveCentroid(int row, int col) const;

  /// @brief Top-left pixel of the primitive box at (row, col) before flips.
  cv::Point primitiveOrigin(int row, int col) const;

  /// @brief Renders the frame: primitives 255, background 0 (CV_8UC1, projector size).
  cv::Mat render() const;

private:
  PatternConfig config_;
  PatternArray array_;
  WordTable words_;
};

}  // namespace sl_projector
