#include "sl_rig/word_table.h"

#include <stdexcept>
#include <string>

namespace sl_projector
{

WordTable::WordTable(const PatternArray& array) : array_(array), alphabet_(array.alphabet()), cols_(array.cols())
{
  long long size = 1;
  for (int i = 0; i < 5; ++i)
    size *= alphabet_;
  if (size > (1LL << 26))
    throw std::invalid_argument("WordTable: alphabet " + std::to_string(alphabet_) +
                                " is too large for a direct table");
  table_.assign(static_cast<size_t>(size), -1);
  for (int r = 1; r + 1 < array.rows(); ++r)
  {
    for (int c = 1; c + 1 < array.cols(); ++c)
    {
      const int w = wordAt(r, c);
      int32_t& slot = table_[static_cast<size_t>(w)];
      if (slot >= 0)
      {
        throw std::invalid_argument("WordTable: pattern of " + std::to_string(array.rows()) + " x " +
                                    std::to_string(array.cols()) + " has duplicate words: (" + std::to_string(r) +
                                    ", " + std::to_string(c) + ") repeats (" + std::to_string(slot / cols_) + ", " +
                                    std::to_string(slot % cols_) + "); use fewer rows or columns");
      }
      slot = r * cols_ + c;
      ++count_;
    }
  }
}

int WordTable::encode(int centre, int north, int west, int south, int east) const
{
  int w = 0;
  for (int v : { centre, north, west, south, east })
  {
    if (v < 1 || v > alphabet_)
      return -1;
    w = w * alphabet_ + (v - 1);
  }
  return w;
}

int WordTable::wordAt(int row, int col) const
{
  if (row < 1 || col < 1 || row + 1 >= array_.rows() || col + 1 >= array_.cols())
    return -1;
  const PatternArray& a = array_;
  return encode(a.value(row, col), a.value(row - 1, col), a.value(row, col - 1), a.value(row + 1, col),
                a.value(row, col + 1));
}

}  // namespace sl_projector
