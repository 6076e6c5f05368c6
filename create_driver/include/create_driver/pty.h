/// @file pty.h
/// @brief A pseudo-terminal pair in raw mode, with an optional symlink to its slave side.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace create_driver
{
/// @brief Owns a pty master (posix_openpt/grantpt/unlockpt) used by the simulator.
///
/// The slave side is put in raw mode and kept open by this object as well, so that the master
/// does not see a hang-up while no client is connected. Like a serial cable with nobody at the
/// other end, output is dropped while no client holds the slave open: opens and closes of the
/// slave are watched with inotify, and when the last client closes, what it left unread is
/// flushed. A client that (re)opens the port therefore reads fresh data first. All I/O is
/// non-blocking.
class Pty
{
public:
  Pty() = default;
  ~Pty();
  Pty(const Pty&) = delete;
  Pty& operator=(const Pty&) = delete;

  /// @brief Creates a new pty pair (closing any previous one).
  bool open(std::string* error);
  /// @brief Closes both sides (clients see EOF/EIO). Does not touch the link.
  void close();
  /// @brief True while a pair is open.
  bool isOpen() const { return master_ >= 0; }
  /// @brief Path of the slave device, e.g. /dev/pts/7.
  const std::string& slavePath() const { return slave_path_; }

  /// @brief Makes @p link_path a symlink to the slave, atomically replacing a stale symlink.
  /// Refuses to replace anything that is not a symlink.
  bool link(const std::string& link_path, std::string* error);
  /// @brief Removes the symlink made by link() if it still points to a pty of ours.
  void unlink();

  /// @brief Waits up to @p timeout_ms for input on the master.
  /// @return true if readable (or hung up)
  bool waitReadable(int timeout_ms) const;
  /// @brief Reads available bytes. @return bytes read, 0 if none, -1 on error.
  long read(uint8_t* buf, size_t len);
  /// @brief Writes what the kernel accepts now, nothing while no client has the slave open.
  /// @return bytes written (the rest is dropped)
  size_t write(const uint8_t* data, size_t len);
  /// @brief Number of clients that have the slave open now (opens minus closes seen by inotify).
  int clients();

private:
  int master_ = -1;
  int slave_keepalive_ = -1;
  int inotify_ = -1;  ///< watches opens and closes of the slave
  int clients_ = 0;   ///< open slave descriptors other than slave_keepalive_
  std::string slave_path_;
  std::string link_path_;
  std::string link_target_;
};

}  // namespace create_driver
