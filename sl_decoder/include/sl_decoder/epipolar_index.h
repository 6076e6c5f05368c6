#pragma once
/// @file epipolar_index.h
/// @brief Which pattern primitives can appear at an image position: the epipolar constraint of the
/// calibrated rig as a lookup table (ROS-free).

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "sl_decoder/decoder_config.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"

namespace sl_decoder
{

/**
 * @brief Precomputed geometry of a rig for decoding.
 *
 * For every primitive, the projector ray through its centroid is traced from min_depth to
 * max_depth and projected into the camera with the full distortion model; the image blocks its
 * curve passes near (within the epipolar tolerance) list the primitive, grouped by primitive value.
 * A blob then looks up its block and value and checks only those few primitives exactly. Built once
 * per rig and config (the decoder's constructor), never per frame. Also holds a camera ray map (undistortion
 * without iteration at run time) and the pattern's average image steps at the nominal depth, which
 * size the neighbour windows. Nothing here assumes a particular rig: resolution, distortion and the
 * side of the projector all come from the calibration.
 */
class EpipolarIndex
{
public:
  /**
   * @brief Builds the tables.
   * @throws std::invalid_argument if the pattern is never visible, or the camera image is empty or
   * larger than sl_projector::kMaxImagePixels (table sizes are computed in 64 bits and checked).
   */
  EpipolarIndex(const sl_projector::Rig& rig, const DecoderConfig& config);

  /// @brief Candidate primitive indices (row * cols + col) near pixel (u, v); a superset.
  /// Grouped by primitive value (ascending), in index order within a value.
  void candidates(float u, float v, const int32_t*& begin, const int32_t*& end) const
  {
    const size_t b = block(u, v) * shape_slots_;
    begin = entries_.data() + block_start_[b];
    end = entries_.data() + block_start_[b + shape_slots_];
  }

  /// @brief The candidates near pixel (u, v) whose primitive value is @p shape, in index order: the
  /// subsequence of candidates(u, v) with that value (empty for a value the pattern lacks).
  void candidates(float u, float v, int shape, const int32_t*& begin, const int32_t*& end) const
  {
    const size_t b = block(u, v) * shape_slots_ + static_cast<size_t>(shape);
    const bool known = shape >= 0 && static_cast<size_t>(shape) < shape_slots_;
    begin = entries_.data() + (known ? block_start_[b] : 0);
    end = entries_.data() + (known ? block_start_[b + 1] : 0);
  }

  /// @brief Undistorted ray (x/z, y/z, 1) of camera pixel (u, v), bilinear in a fine table.
  /// (Inline: the decoder calls it per blob.)
  Eigen::Vector3d cameraRay(double u, double v) const;

  /// @brief Origin of every projector ray (the projector centre), camera frame, m.
  const Eigen::Vector3d& projectorOrigin() const { return projector_origin_; }
  /// @brief Unit direction of the projector ray of primitive @p index, camera frame.
  const Eigen::Vector3d& projectorDirection(int index) const { return directions_[static_cast<size_t>(index)]; }

  /// @brief Average image displacement from a primitive to its east neighbour at the nominal depth, px.
  const Eigen::Vector2d& stepEast() const { return step_east_; }
  /// @brief Average image displacement from a primitive to its south neighbour at the nominal depth, px.
  const Eigen::Vector2d& stepSouth() const { return step_south_; }
  /// @brief True if epipolar curves run along pattern rows (candidates differ by column), false if
  /// along columns.
  bool epipolarAlongRows() const { return along_rows_; }

  /// @brief Primitives whose curve enters the image at all.
  int visiblePrimitives() const { return visible_; }

private:
  static constexpr int kBlockShift = 2;  // 4 px blocks
  static constexpr int kRayStep = 4;     // ray table spacing, px

  /// The block of pixel (u, v), clamped to the image.
  size_t block(float u, float v) const
  {
    int bx = static_cast<int>(u + 0.5f) >> kBlockShift;
    int by = static_cast<int>(v + 0.5f) >> kBlockShift;
    bx = bx < 0 ? 0 : (bx >= blocks_x_ ? blocks_x_ - 1 : bx);
    by = by < 0 ? 0 : (by >= blocks_y_ ? blocks_y_ - 1 : by);
    return static_cast<size_t>(by) * static_cast<size_t>(blocks_x_) + static_cast<size_t>(bx);
  }
  /// Fills block_start_ and entries_ from per-block lists, each grouped by primitive value.
  void storeBlocks(const std::vector<std::vector<int32_t>>& lists, const std::vector<int>& values);

  int blocks_x_ = 0, blocks_y_ = 0;
  size_t shape_slots_ = 1;            // primitive values 0 .. shape_slots_ - 1
  std::vector<int32_t> block_start_;  // CSR offsets per (block, value), blocks * shape_slots_ + 1
  std::vector<int32_t> entries_;
  int ray_w_ = 0, ray_h_ = 0;
  std::vector<Eigen::Vector2d> ray_table_;  // undistorted normalised coordinates on a kRayStep grid
  Eigen::Vector3d projector_origin_;
  std::vector<Eigen::Vector3d> directions_;
  Eigen::Vector2d step_east_, step_south_;
  bool along_rows_ = true;
  int visible_ = 0;
};

inline Eigen::Vector3d EpipolarIndex::cameraRay(double u, double v) const
{
  double fx = u / kRayStep, fy = v / kRayStep;
  fx = std::min(std::max(fx, 0.0), static_cast<double>(ray_w_ - 1) - 1e-9);
  fy = std::min(std::max(fy, 0.0), static_cast<double>(ray_h_ - 1) - 1e-9);
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  const double ax = fx - ix, ay = fy - iy;
  const size_t w = static_cast<size_t>(ray_w_);
  const size_t k00 = static_cast<size_t>(iy) * w + static_cast<size_t>(ix);
  const Eigen::Vector2d& p00 = ray_table_[k00];
  const Eigen::Vector2d& p10 = ray_table_[k00 + 1];
  const Eigen::Vector2d& p01 = ray_table_[k00 + w];
  const Eigen::Vector2d& p11 = ray_table_[k00 + w + 1];
  const Eigen::Vector2d q = (1 - ay) * ((1 - ax) * p00 + ax * p10) + ay * ((1 - ax) * p01 + ax * p11);
  return { q.x(), q.y(), 1.0 };
}

}  // namespace sl_decoder
