/**
 * @file
 * The record of the files a player could not use, for the log and the diagnostics.
 */
#pragma once

#include <cstddef>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace sl_camera
{

/**
 * Distinct names of files that could not be read, in the order they were first met. Written by
 * the capture thread, read by the diagnostics and the log: thread-safe. A file stays listed once
 * it failed (a looping player meets it again and again; it is counted once).
 */
class UnreadableFiles
{
public:
  /**
   * Records @p file.
   * @return true if it was not recorded before
   */
  bool add(const std::string& file);

  /** Number of distinct files recorded. */
  std::size_t count() const;

  /** The first @p n files recorded (fewer if there are fewer). */
  std::vector<std::string> first(std::size_t n) const;

  /**
   * The files recorded after the first @p index ones, in order: a reader that keeps the count it
   * has seen gets each name once (e.g. for a throttled log line of the new names).
   */
  std::vector<std::string> from(std::size_t index) const;

  /**
   * "a.png, b.png and 3 more": at most @p max_names names, then how many are left out; "none"
   * when nothing is recorded.
   */
  std::string summary(std::size_t max_names) const;

  /** Joins @p names with ", " (for log lines). */
  static std::string join(const std::vector<std::string>& names);

private:
  mutable std::mutex mutex_;
  std::set<std::string> known_;
  std::vector<std::string> files_;
};

}  // namespace sl_camera
