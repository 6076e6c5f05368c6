#pragma once
/// @file de_bruijn.h
/// @brief De Bruijn sequence generation (ROS-free).

#include <string>
#include <vector>

namespace sl_projector
{

/**
 * @brief Generates the cyclic De Bruijn sequence B(P, n) over the symbols 1..P.
 *
 * Every word of length @p window over {1..P} appears exactly once as a cyclic window, so the
 * sequence has P^n symbols. The symbols are produced by concatenating, in lexicographic order, the
 * Lyndon words whose length divides n (Fredricksen-Kessler-Maiorana) over the digits 0..P-1 and
 * mapping digit d to symbol P - d. With P = 4 this gives exactly the prototype's sequences
 * G(4,3) = 4443442441...2111 and G(4,2) = 4434241332312211 (Hsieh's order).
 *
 * @param alphabet P, the number of symbols (>= 2).
 * @param window n, the window length (>= 1).
 * @return the P^n symbols, each in 1..P.
 * @throws std::invalid_argument if P < 2, n < 1 or P^n exceeds 2^24 symbols.
 */
std::vector<int> deBruijnSequence(int alphabet, int window);

/**
 * @brief Formats a symbol sequence as a string of digits (symbols must be 1..9).
 * @throws std::invalid_argument if a symbol is outside 0..9.
 */
std::string sequenceToString(const std::vector<int>& sequence);

}  // namespace sl_projector
