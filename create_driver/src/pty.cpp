#include "create_driver/pty.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace create_driver
{
namespace
{
std::string errnoText(const char* what)
{
  return std::string(what) + ": " + std::strerror(errno);
}
}  // namespace

Pty::~Pty()
{
  close();
}

bool Pty::open(std::string* error)
{
  close();
  const int m = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (m < 0)
  {
    if (error)
      *error = errnoText("posix_openpt");
    return false;
  }
  char name[256];
  if (::grantpt(m) != 0 || ::unlockpt(m) != 0 || ::ptsname_r(m, name, sizeof(name)) != 0)
  {
    if (error)
      *error = errnoText("grantpt/unlockpt/ptsname");
    ::close(m);
    return false;
  }
  const int s = ::open(name, O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (s < 0)
  {
    if (error)
      *error = errnoText("open slave");
    ::close(m);
    return false;
  }
  termios tio{};
  if (::tcgetattr(s, &tio) == 0)
  {
    ::cfmakeraw(&tio);
    ::cfsetispeed(&tio, B57600);
    ::cfsetospeed(&tio, B57600);
    ::tcsetattr(s, TCSANOW, &tio);
  }
  // Opens and closes of the slave from now on are the clients' (ours came before the watch).
  const int in = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (in < 0 || ::inotify_add_watch(in, name, IN_OPEN | IN_CLOSE_WRITE | IN_CLOSE_NOWRITE) < 0)
  {
    if (error)
      *error = errnoText("inotify on the pty slave");
    if (in >= 0)
      ::close(in);
    ::close(s);
    ::close(m);
    return false;
  }
  const int flags = ::fcntl(m, F_GETFL);
  ::fcntl(m, F_SETFL, flags | O_NONBLOCK);
  inotify_ = in;
  clients_ = 0;
  master_ = m;
  slave_keepalive_ = s;
  slave_path_ = name;
  return true;
}

void Pty::close()
{
  if (inotify_ >= 0)
    ::close(inotify_);
  inotify_ = -1;
  clients_ = 0;
  if (slave_keepalive_ >= 0)
    ::close(slave_keepalive_);
  if (master_ >= 0)
    ::close(master_);
  slave_keepalive_ = -1;
  master_ = -1;
}

bool Pty::link(const std::string& link_path, std::string* error)
{
  if (link_path.empty())
    return true;
  if (!isOpen())
  {
    if (error)
      *error = "no pty open";
    return false;
  }
  struct stat st
  {
  };
  if (::lstat(link_path.c_str(), &st) == 0 && !S_ISLNK(st.st_mode))
  {
    if (error)
      *error = "refusing to replace " + link_path + ": it exists and is not a symlink";
    return false;
  }
  const std::string tmp = link_path + ".tmp" + std::to_string(::getpid());
  ::unlink(tmp.c_str());
  if (::symlink(slave_path_.c_str(), tmp.c_str()) != 0)
  {
    if (error)
      *error = errnoText(("symlink " + tmp).c_str());
    return false;
  }
  if (::rename(tmp.c_str(), link_path.c_str()) != 0)
  {
    if (error)
      *error = errnoText(("rename to " + link_path).c_str());
    ::unlink(tmp.c_str());
    return false;
  }
  link_path_ = link_path;
  link_target_ = slave_path_;
  return true;
}

void Pty::unlink()
{
  if (link_path_.empty())
    return;
  std::vector<char> buf(4096);
  const ssize_t n = ::readlink(link_path_.c_str(), buf.data(), buf.size() - 1);
  if (n > 0 && std::string(buf.data(), static_cast<size_t>(n)) == link_target_)
    ::unlink(link_path_.c_str());
  link_path_.clear();
  link_target_.clear();
}

bool Pty::waitReadable(int timeout_ms) const
{
  if (master_ < 0)
    return false;
  pollfd p{};
  p.fd = master_;
  p.events = POLLIN;
  const int r = ::poll(&p, 1, timeout_ms);
  return r > 0 && (p.revents & (POLLIN | POLLHUP | POLLERR)) != 0;
}

long Pty::read(uint8_t* buf, size_t len)
{
  if (master_ < 0)
    return -1;
  const ssize_t n = ::read(master_, buf, len);
  if (n < 0)
    return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? 0 : -1;
  return static_cast<long>(n);
}

int Pty::clients()
{
  if (inotify_ < 0)
    return 0;
  alignas(inotify_event) char buf[4096];
  ssize_t n;
  while ((n = ::read(inotify_, buf, sizeof(buf))) > 0)
  {
    for (ssize_t off = 0; off < n;)
    {
      const auto* ev = reinterpret_cast<const inotify_event*>(buf + off);
      if (ev->mask & IN_OPEN)
        ++clients_;
      if (ev->mask & (IN_CLOSE_WRITE | IN_CLOSE_NOWRITE))
      {
        clients_ = clients_ > 0 ? clients_ - 1 : 0;
        // The last client left: what it did not read would be stale for the next one.
        if (clients_ == 0 && slave_keepalive_ >= 0)
          ::tcflush(slave_keepalive_, TCIFLUSH);
      }
      off += static_cast<ssize_t>(sizeof(inotify_event) + ev->len);
    }
  }
  return clients_;
}

size_t Pty::write(const uint8_t* data, size_t len)
{
  if (master_ < 0)
    return 0;
  if (clients() == 0)
    return 0;  // nobody at the other end of the cable
  size_t done = 0;
  while (done < len)
  {
    const ssize_t n = ::write(master_, data + done, len - done);
    if (n <= 0)
    {
      if (n < 0 && errno == EINTR)
        continue;
      break;  // EAGAIN: the buffer is full, nobody reads; drop the rest
    }
    done += static_cast<size_t>(n);
  }
  return done;
}

}  // namespace create_driver
