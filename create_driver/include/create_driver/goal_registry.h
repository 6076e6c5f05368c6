/// @file goal_registry.h
/// @brief The action server's handles of running goals, by DriverCore's goal id.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

namespace create_driver
{
/// @brief Handles of the goals that have not ended, keyed by goal id (GoalStart::id). @p Handle
/// needs only copying and operator==. Not thread-safe: the caller serialises access.
template <typename Handle>
class GoalRegistry
{
public:
  /// @brief Keeps @p handle for goal @p id (replacing one kept for the same id).
  void add(uint64_t id, const Handle& handle) { handles_[id] = handle; }

  /// @brief The handle of goal @p id, removed: the goal has ended. Empty for an unknown id.
  std::optional<Handle> take(uint64_t id)
  {
    auto it = handles_.find(id);
    if (it == handles_.end())
      return std::nullopt;
    Handle h = it->second;
    handles_.erase(it);
    return h;
  }

  /// @brief The handle of goal @p id, kept. Empty for an unknown id.
  std::optional<Handle> find(uint64_t id) const
  {
    auto it = handles_.find(id);
    if (it == handles_.end())
      return std::nullopt;
    return it->second;
  }

  /// @brief Ids of the goals whose handle equals @p handle (a cancel request names the handle).
  std::vector<uint64_t> idsOf(const Handle& handle) const
  {
    std::vector<uint64_t> ids;
    for (const auto& kv : handles_)
      if (kv.second == handle)
        ids.push_back(kv.first);
    return ids;
  }

  /// @brief Number of goals kept.
  size_t size() const { return handles_.size(); }

private:
  std::map<uint64_t, Handle> handles_;
};

}  // namespace create_driver
