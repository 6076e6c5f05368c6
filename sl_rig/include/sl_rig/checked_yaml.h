#pragma once
/// @file checked_yaml.h
/// @brief Mappings of the stack's YAML files (rig files, scene files) with a known set of keys
/// (ROS-free; yaml-cpp). A key outside the set is refused, so that a misspelt optional key is never
/// ignored silently: `camera.Kx: unknown key, did you mean 'K'? (allowed: D, K, height, width)`.
/// The messages start with the key; the reader of a file puts the file's name before them.

#include <set>
#include <string>

#include <yaml-cpp/yaml.h>

namespace sl_rig
{

/**
 * @brief Checks that every key of the mapping @p node is one of @p allowed.
 * @param prefix put before each key in the messages: the path of @p node with a trailing dot
 *        ("camera.", "objects[0].texture."), empty at the top level.
 * @throws std::invalid_argument when @p node is not a mapping ("<path>: must be a mapping", the
 *         path "<top level>" for an empty prefix); for an unknown key "<prefix><key>: unknown key
 *         (allowed: a, b)", with ", did you mean '<k>'?" after "unknown key" when one allowed key is
 *         close (nearestKey()); for a key that is not a name (empty, a list or a mapping)
 *         "<prefix><key as written>: a key must be a name, not ... (line N)".
 */
void checkKeys(const YAML::Node& node, const std::set<std::string>& allowed, const std::string& prefix = "");

/**
 * @brief The element of @p candidates nearest to @p key in edit distance (insertions, deletions,
 * substitutions, and swaps of neighbours), or "" when none is within max(1, key length / 3) edits
 * or two are equally near.
 */
std::string nearestKey(const std::string& key, const std::set<std::string>& candidates);

}  // namespace sl_rig
