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

/**
 * The log of the unreadable files: each name once, new names at most every @p interval. Not
 * thread-safe: one thread logs.
 */
class UnreadableFilesLog
{
public:
  /** @param interval shortest interval between two log lines, s */
  explicit UnreadableFilesLog(double interval) : interval_(interval) {}

  /**
   * The names of @p files not logged yet, when a line is due at @p now (seconds of any one clock);
   * empty otherwise. The names returned count as logged.
   */
  std::vector<std::string> due(const UnreadableFiles& files, double now);

  /** Names logged so far. */
  std::size_t logged() const { return logged_; }

private:
  double interval_;
  std::size_t logged_ = 0;
  bool have_logged_ = false;
  double last_ = 0.0;
};

}  // namespace sl_camera
