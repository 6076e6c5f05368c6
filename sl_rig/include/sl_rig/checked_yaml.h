#pragma once
/// @file checked_yaml.h
/// @brief Mappings of the stack's YAML files (rig files, scene files) with a known set of keys
/// (ROS-free; yaml-cpp). A key outside the set is refused, so that a misspelt optional key is never
/// ignored silently: `camera.Kx: unknown key, did you mean 'K'? (allowed: D, K, height, width)`.
/// The messages start with the key; the reader of a file puts the file's name before them.
/// readFileText() and parseMappingFile() are the loading both readers share, each throwing its own
/// error type.

#include <fstream>
#include <set>
#include <sstream>
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

/**
 * @brief The whole text of file @p path.
 * @throws Error "<path>: cannot open the <what>" (@p what: "calibration file", "scene file").
 */
template <class Error>
std::string readFileText(const std::string& path, const std::string& what)
{
  std::ifstream in(path);
  if (!in)
    throw Error(path + ": cannot open the " + what);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

/**
 * @brief Parses @p text, the YAML of file @p source, whose top level must be a mapping, and returns
 * what @p parse makes of that mapping.
 * @param expected said after "must be a mapping" when it is not (e.g. " with 'objects'").
 * @throws Error "<source>: not valid YAML: ...", "<source>: <top level>: must be a mapping<expected>
 *         (is the file empty?)", or "<source>: <what>" for a YAML::Exception out of @p parse (a
 *         backstop: @p parse names the keys itself).
 */
template <class Error, class Parse>
auto parseMappingFile(const std::string& text, const std::string& source, const std::string& expected, Parse parse)
    -> decltype(parse(YAML::Node()))
{
  YAML::Node root;
  try
  {
    root = YAML::Load(text);
  }
  catch (const YAML::Exception& e)
  {
    throw Error(source + ": not valid YAML: " + e.what());
  }
  if (!root || !root.IsMap())
    throw Error(source + ": <top level>: must be a mapping" + expected + " (is the file empty?)");
  try
  {
    return parse(root);
  }
  catch (const YAML::Exception& e)
  {
    throw Error(source + ": " + e.what());
  }
}

}  // namespace sl_rig
