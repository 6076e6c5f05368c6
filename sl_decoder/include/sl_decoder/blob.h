#pragma once
/// @file blob.h
/// @brief A candidate primitive found in the camera image and what decoding learned about it.

#include <cstdint>

namespace sl_decoder
{

/// @brief Directions to the four grid neighbours, in pattern terms.
enum Direction
{
  kNorth = 0,
  kWest = 1,
  kSouth = 2,
  kEast = 3
};

/**
 * @brief One connected bright component of the thresholded image.
 */
struct Blob
{
  // Detection.
  float u = 0.f;         ///< intensity-weighted centroid column, px (pixel centres at integers)
  float v = 0.f;         ///< intensity-weighted centroid row, px
  int x0 = 0, y0 = 0;    ///< bounding box, first column and row
  int x1 = 0, y1 = 0;    ///< bounding box, one past the last column and row
  int area = 0;          ///< foreground pixels
  float contrast = 0.f;  ///< peak height above the local mean, grey levels
  int level = 0;         ///< 0: found by the local threshold; k > 0: split out of a merged, blurred
                         ///< component at the k-th raised threshold (near range, heavy defocus)
  // Identification.
  int shape = 0;            ///< primitive value 1..4, 0 when not identified
  float correlation = 0.f;  ///< NCC with the chosen template
  float margin = 0.f;       ///< best minus second-best NCC
  // Neighbours (indices into the blob list, -1 when none).
  int neighbour[4] = { -1, -1, -1, -1 };
  // Correspondence.
  int row = -1;                ///< pattern row when decoded, else -1
  int col = -1;                ///< pattern column when decoded, else -1
  int support = 0;             ///< neighbours consistent with (row, col)
  float epipolar_error = 0.f;  ///< distance from the epipolar curve of (row, col), px
  float confidence = 0.f;      ///< 0..1, see Decoder
  // 3D point in the camera optical frame, m (valid when decoded and depth succeeded).
  bool valid = false;               ///< a 3D point was produced
  float x = 0.f, y = 0.f, z = 0.f;  ///< m

  /// @brief Bounding-box width.
  int width() const { return x1 - x0; }
  /// @brief Bounding-box height.
  int height() const { return y1 - y0; }
  /// @brief True once (row, col) is assigned.
  bool decoded() const { return row >= 0; }
};

}  // namespace sl_decoder
