#pragma once
/// @file word_table.h
/// @brief O(1) lookup from a (centre, north, west, south, east) word to its pattern position.

#include <cstdint>
#include <vector>

#include "sl_rig/pattern_array.h"

namespace sl_projector
{

/// @brief A position in the pattern array.
struct GridPos
{
  int row = -1;  ///< pattern row, -1 when invalid
  int col = -1;  ///< pattern column, -1 when invalid
  /// @brief True for a real position.
  bool valid() const { return row >= 0 && col >= 0; }
  bool operator==(const GridPos& o) const { return row == o.row && col == o.col; }
};

/**
 * @brief Direct-indexed table of the words of all interior elements.
 *
 * A word is (centre, north, west, south, east), each a symbol 1..P; it is packed into an index in
 * [0, P^5) with centre as the most significant digit. Lookup and the inverse are O(1).
 */
class WordTable
{
public:
  /**
   * @brief Builds the table for all interior elements of @p array.
   * @throws std::invalid_argument if two interior elements share a word; the message names both.
   */
  explicit WordTable(const PatternArray& array);

  /// @brief Packs five symbols (each 1..P) into a word index; returns -1 if any is out of range.
  int encode(int centre, int north, int west, int south, int east) const;

  /// @brief The position whose word is @p word, or an invalid GridPos.
  GridPos lookup(int word) const
  {
    if (word < 0 || word >= static_cast<int>(table_.size()))
      return GridPos{};
    const int32_t v = table_[static_cast<size_t>(word)];
    return v < 0 ? GridPos{} : GridPos{ v / cols_, v % cols_ };
  }

  /// @brief The position for five symbols, or an invalid GridPos.
  GridPos lookup(int centre, int north, int west, int south, int east) const
  {
    return lookup(encode(centre, north, west, south, east));
  }

  /// @brief The word of the interior element at (row, col), or -1 for a border or outside element.
  int wordAt(int row, int col) const;

  /// @brief Number of interior elements (all with unique words).
  int size() const { return count_; }

  /// @brief Alphabet size P.
  int alphabet() const { return alphabet_; }

private:
  PatternArray array_;  ///< own copy: the table stays valid whatever happens to the caller's array
  int alphabet_;
  int cols_;
  int count_ = 0;
  std::vector<int32_t> table_;  ///< word -> row * cols + col, or -1
};

}  // namespace sl_projector
