#pragma once
/// @file pattern_array.h
/// @brief The 2D De Bruijn array of primitive values (Griffin et al. construction, ROS-free).

#include <cstddef>
#include <vector>

namespace sl_projector
{

/**
 * @brief A rows x cols array of primitive values in 1..P.
 *
 * Row 0 is the De Bruijn sequence B(P,3) (columns wrap cyclically past its length). Row r+1 is row
 * r with the r-th symbol of B(P,2) added to every element, wrapped back into 1..P (a sum above P
 * wraps again; there is no value 0). The (centre, north, west, south, east) word of every interior
 * element is then unique as long as rows <= |B(P,2)| + 2 and cols <= |B(P,3)| + 2; WordTable
 * checks this for any size.
 */
class PatternArray
{
public:
  /**
   * @brief Builds the array.
   * @param rows number of rows (>= 3).
   * @param cols number of columns (>= 3).
   * @param alphabet P (>= 2).
   * @throws std::invalid_argument naming the offending argument.
   */
  PatternArray(int rows = 16, int cols = 64, int alphabet = 4);

  /// @brief Number of rows.
  int rows() const { return rows_; }
  /// @brief Number of columns.
  int cols() const { return cols_; }
  /// @brief Alphabet size P.
  int alphabet() const { return alphabet_; }
  /// @brief Value (1..P) at (row, col); no bounds check.
  int value(int row, int col) const { return values_[static_cast<size_t>(row * cols_ + col)]; }
  /// @brief Value at (row, col), or 0 outside the array.
  int valueOrZero(int row, int col) const
  {
    return (row < 0 || col < 0 || row >= rows_ || col >= cols_) ? 0 : value(row, col);
  }
  /// @brief Row-major values.
  const std::vector<int>& values() const { return values_; }
  /// @brief The row sequence B(P,3) used for row 0.
  const std::vector<int>& rowSequence() const { return row_sequence_; }
  /// @brief The column-offset sequence B(P,2).
  const std::vector<int>& offsetSequence() const { return offset_sequence_; }

private:
  int rows_;
  int cols_;
  int alphabet_;
  std::vector<int> row_sequence_;
  std::vector<int> offset_sequence_;
  std::vector<int> values_;
};

/// @brief Adds two symbols of 1..P and wraps the sum back into 1..P.
inline int wrapAdd(int a, int b, int alphabet)
{
  return (a + b - 1) % alphabet + 1;
}

}  // namespace sl_projector
