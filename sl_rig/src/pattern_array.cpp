#include "sl_rig/pattern_array.h"

#include <stdexcept>
#include <string>

#include "sl_rig/de_bruijn.h"

namespace sl_projector
{

PatternArray::PatternArray(int rows, int cols, int alphabet) : rows_(rows), cols_(cols), alphabet_(alphabet)
{
  if (alphabet < 2)
    throw std::invalid_argument("PatternArray: alphabet must be >= 2, got " + std::to_string(alphabet));
  if (rows < 3)
    throw std::invalid_argument("PatternArray: rows must be >= 3, got " + std::to_string(rows));
  if (cols < 3)
    throw std::invalid_argument("PatternArray: cols must be >= 3, got " + std::to_string(cols));
  row_sequence_ = deBruijnSequence(alphabet, 3);
  offset_sequence_ = deBruijnSequence(alphabet, 2);
  values_.resize(static_cast<size_t>(rows) * static_cast<size_t>(cols));
  const size_t nr = row_sequence_.size();
  const size_t no = offset_sequence_.size();
  for (int c = 0; c < cols; ++c)
    values_[static_cast<size_t>(c)] = row_sequence_[static_cast<size_t>(c) % nr];
  for (int r = 1; r < rows; ++r)
  {
    const int offset = offset_sequence_[static_cast<size_t>(r - 1) % no];
    for (int c = 0; c < cols; ++c)
      values_[static_cast<size_t>(r * cols + c)] = wrapAdd(value(r - 1, c), offset, alphabet);
  }
}

}  // namespace sl_projector
