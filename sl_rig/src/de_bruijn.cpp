#include "sl_rig/de_bruijn.h"

#include <stdexcept>

namespace sl_projector
{

std::vector<int> deBruijnSequence(int alphabet, int window)
{
  if (alphabet < 2)
    throw std::invalid_argument("deBruijnSequence: alphabet must be >= 2, got " + std::to_string(alphabet));
  if (window < 1)
    throw std::invalid_argument("deBruijnSequence: window must be >= 1, got " + std::to_string(window));
  long long length = 1;
  for (int i = 0; i < window; ++i)
  {
    length *= alphabet;
    if (length > (1LL << 24))
      throw std::invalid_argument("deBruijnSequence: alphabet^window is too large");
  }

  // Iterative FKM: walk all prenecklaces in lexicographic order; emit a[1..p] for Lyndon words
  // (p = position of the last increment) whose length divides the window.
  std::vector<int> a(static_cast<size_t>(window) + 1, 0);
  std::vector<int> out;
  out.reserve(static_cast<size_t>(length));
  int p = 1;
  out.push_back(alphabet);  // the word 0^n contributes the single digit 0 (symbol P)
  while (true)
  {
    // next prenecklace: increment the last position that is not the maximum digit
    int i = window;
    while (i > 0 && a[static_cast<size_t>(i)] == alphabet - 1)
      --i;
    if (i == 0)
      break;
    ++a[static_cast<size_t>(i)];
    for (int j = i + 1; j <= window; ++j)
      a[static_cast<size_t>(j)] = a[static_cast<size_t>(j - i)];
    p = i;
    if (window % p == 0)
      for (int j = 1; j <= p; ++j)
        out.push_back(alphabet - a[static_cast<size_t>(j)]);
  }
  return out;
}

std::string sequenceToString(const std::vector<int>& sequence)
{
  std::string s;
  s.reserve(sequence.size());
  for (int v : sequence)
  {
    if (v < 0 || v > 9)
      throw std::invalid_argument("sequenceToString: symbol " + std::to_string(v) + " is not a single digit");
    s.push_back(static_cast<char>('0' + v));
  }
  return s;
}

}  // namespace sl_projector
