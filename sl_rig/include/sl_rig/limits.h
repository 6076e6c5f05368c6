#pragma once
/// @file limits.h
/// @brief Size limits of the images a rig describes (ROS-free).
///
/// Everything downstream (the projector frame, the simulator's images, the decoder's lookup
/// tables) allocates per pixel and indexes with int, so a rig is refused before any of it could
/// overflow or ask for gigabytes.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace sl_projector
{

/// @brief Largest camera or projector image side accepted in a rig, px.
constexpr int kMaxImageSide = 16384;

/// @brief Largest camera or projector image area accepted in a rig, px (64 Mpx: 8192 x 8192, or
/// 16384 x 4096). Per-pixel tables of this size index safely with int.
constexpr int64_t kMaxImagePixels = int64_t{ 1 } << 26;

/**
 * @brief Cells of a @p cols x @p rows table (an image or a lookup grid over one), computed without
 * overflow.
 * @param what names the table in the error message.
 * @return cols * rows.
 * @throws std::invalid_argument if a side is < 1 or the product exceeds kMaxImagePixels.
 */
inline size_t checkedCells(int64_t cols, int64_t rows, const std::string& what)
{
  const std::string size = std::to_string(cols) + " x " + std::to_string(rows) + " cells";
  if (cols < 1 || rows < 1)
    throw std::invalid_argument(what + ": " + size + ": the image is empty");
  // Each side is checked first, so the product cannot overflow 64 bits.
  if (cols > kMaxImagePixels || rows > kMaxImagePixels || cols * rows > kMaxImagePixels)
    throw std::invalid_argument(what + ": " + size + ", more than the " + std::to_string(kMaxImagePixels) +
                                " allowed: the image is too large");
  return static_cast<size_t>(cols) * static_cast<size_t>(rows);
}

}  // namespace sl_projector
