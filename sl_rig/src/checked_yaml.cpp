#include "sl_rig/checked_yaml.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace sl_rig
{

namespace
{
// Optimal string alignment distance: Levenshtein plus the swap of two neighbours ("rosw" -> "rows").
size_t editDistance(const std::string& a, const std::string& b)
{
  const size_t n = a.size(), m = b.size();
  std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
  for (size_t i = 0; i <= n; ++i)
    d[i][0] = i;
  for (size_t j = 0; j <= m; ++j)
    d[0][j] = j;
  for (size_t i = 1; i <= n; ++i)
    for (size_t j = 1; j <= m; ++j)
    {
      const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({ d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost });
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

// A key as the file wrote it, on one line (`? :` is the mapping {~: ~}).
std::string shownKey(const YAML::Node& key)
{
  if (key.IsNull())
    return "<empty key>";
  YAML::Node copy = YAML::Clone(key);
  copy.SetStyle(YAML::EmitterStyle::Flow);
  YAML::Emitter out;
  out << copy;
  return out.c_str();
}
}  // namespace

std::string nearestKey(const std::string& key, const std::set<std::string>& candidates)
{
  // Long keys allow more typos; a key of 1 to 5 characters one.
  const size_t limit = std::max<size_t>(1, key.size() / 3);
  std::string best;
  size_t best_distance = limit + 1;
  bool tie = false;
  for (const std::string& c : candidates)
  {
    const size_t d = editDistance(key, c);
    if (d < best_distance)
    {
      best = c;
      best_distance = d;
      tie = false;
    }
    else if (d == best_distance)
    {
      tie = true;
    }
  }
  return tie || best_distance > limit ? std::string() : best;
}

void checkKeys(const YAML::Node& node, const std::set<std::string>& allowed, const std::string& prefix)
{
  if (!node.IsMap())
  {
    const std::string path = prefix.empty() ? std::string("<top level>") : prefix.substr(0, prefix.size() - 1);
    throw std::invalid_argument(path + ": must be a mapping");
  }
  for (const auto& kv : node)
  {
    // A key such as `? :` (null) or `[1]` (a list) is not a name; as<std::string>() would throw a
    // YAML::TypedBadConversion that names neither file nor key.
    if (!kv.first.IsScalar())
      throw std::invalid_argument(prefix + shownKey(kv.first) + ": a key must be a name, not " +
                                  (kv.first.IsNull() ? "empty" : "a list or a mapping") + " (line " +
                                  std::to_string(kv.first.Mark().line + 1) + ")");
    const std::string key = kv.first.Scalar();
    if (allowed.count(key))
      continue;
    std::string list;
    for (const std::string& a : allowed)
      list += (list.empty() ? "" : ", ") + a;
    const std::string nearest = nearestKey(key, allowed);
    throw std::invalid_argument(prefix + key + ": unknown key" +
                                (nearest.empty() ? std::string() : ", did you mean '" + nearest + "'?") +
                                " (allowed: " + list + ")");
  }
}

}  // namespace sl_rig
