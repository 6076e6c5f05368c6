// create_sim's building blocks over a real pseudo-terminal, driven by a minimal "third-party"
// Open Interface client written with plain POSIX calls and its own checksum scan (it does not use
// this package's parser), to check that the simulator follows the spec on the wire.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <mutex>
#include <thread>

#include "create_driver/pty.h"
#include "create_driver/sim_robot.h"

using create_driver::Bytes;
namespace cd = create_driver;

namespace
{
std::string tempLink(const char* tag)
{
  return "/tmp/create_driver_pty_test_" + std::string(tag) + "_" + std::to_string(::getpid());
}

// Runs a SimRobot behind a Pty on a thread, like create_sim does.
class SimThread
{
public:
  explicit SimThread(const std::string& link)
  {
    std::string err;
    ok = pty.open(&err) && pty.link(link, &err);
    error = err;
    thread = std::thread([this] { loop(); });
  }
  ~SimThread()
  {
    stop = true;
    thread.join();
    pty.unlink();
    pty.close();
  }
  void loop()
  {
    auto last = std::chrono::steady_clock::now();
    uint8_t buf[256];
    Bytes out;
    while (!stop)
    {
      pty.waitReadable(2);
      std::lock_guard<std::mutex> lock(mutex);
      long n;
      while ((n = pty.read(buf, sizeof(buf))) > 0)
        robot.receive(buf, static_cast<size_t>(n));
      const auto now = std::chrono::steady_clock::now();
      robot.step(std::chrono::duration<double>(now - last).count());
      last = now;
      out.clear();
      robot.takeOutput(out);
      if (!out.empty())
        pty.write(out.data(), out.size());
    }
  }
  cd::Pty pty;
  cd::SimRobot robot;
  std::mutex mutex;
  std::atomic<bool> stop{ false };
  std::thread thread;
  bool ok = false;
  std::string error;
};

int openClient(const std::string& path)
{
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY);
  if (fd < 0)
    return -1;
  termios t{};
  ::tcgetattr(fd, &t);
  ::cfmakeraw(&t);
  ::cfsetispeed(&t, B57600);
  ::cfsetospeed(&t, B57600);
  ::tcsetattr(fd, TCSANOW, &t);
  ::tcflush(fd, TCIOFLUSH);
  return fd;
}

void writeAll(int fd, const Bytes& b)
{
  ASSERT_EQ(::write(fd, b.data(), b.size()), static_cast<ssize_t>(b.size()));
}

// Reads until @p want bytes arrived or @p timeout_s passed.
Bytes readFor(int fd, size_t want, double timeout_s)
{
  Bytes out;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  uint8_t buf[256];
  while (out.size() < want && std::chrono::steady_clock::now() < end)
  {
    pollfd p{ fd, POLLIN, 0 };
    if (::poll(&p, 1, 20) > 0)
    {
      const ssize_t n = ::read(fd, buf, sizeof(buf));
      if (n <= 0)
        break;
      out.insert(out.end(), buf, buf + n);
    }
  }
  return out;
}

// Independent frame scanner: header 19, length, payload, checksum summing to 0.
struct Frame
{
  Bytes payload;
};
std::vector<Frame> scanFrames(const Bytes& b)
{
  std::vector<Frame> frames;
  size_t i = 0;
  while (i + 2 < b.size())
  {
    if (b[i] != 19)
    {
      ++i;
      continue;
    }
    const size_t n = b[i + 1];
    if (i + n + 3 > b.size())
      break;
    unsigned sum = 0;
    for (size_t k = 0; k < n + 3; ++k)
      sum += b[i + k];
    if ((sum & 0xFF) == 0)
    {
      frames.push_back(Frame{ Bytes(b.begin() + static_cast<long>(i) + 2, b.begin() + static_cast<long>(i + 2 + n)) });
      i += n + 3;
    }
    else
    {
      ++i;
    }
  }
  return frames;
}
}  // namespace

TEST(Pty, LinkReplacesStaleSymlinkButNotFiles)
{
  const std::string link = tempLink("stale");
  ::unlink(link.c_str());
  ASSERT_EQ(::symlink("/nonexistent/dev", link.c_str()), 0);
  cd::Pty pty;
  std::string err;
  ASSERT_TRUE(pty.open(&err)) << err;
  ASSERT_TRUE(pty.link(link, &err)) << err;
  char target[256] = {};
  ASSERT_GT(::readlink(link.c_str(), target, sizeof(target) - 1), 0);
  EXPECT_EQ(std::string(target), pty.slavePath());
  pty.unlink();
  struct stat st
  {
  };
  EXPECT_NE(::lstat(link.c_str(), &st), 0) << "link not removed";

  // A regular file is never replaced.
  {
    std::ofstream f(link);
    f << "keep";
  }
  EXPECT_FALSE(pty.link(link, &err));
  EXPECT_NE(err.find("not a symlink"), std::string::npos);
  ::unlink(link.c_str());
}

TEST(Pty, ThirdPartyClientStreamsAndDrives)
{
  const std::string link = tempLink("client");
  SimThread sim(link);
  ASSERT_TRUE(sim.ok) << sim.error;
  const int fd = openClient(link);
  ASSERT_GE(fd, 0);
  // Start, Safe, Stream [7, 19, 20, 35].
  writeAll(fd, { 128, 131, 148, 4, 7, 19, 20, 35 });
  const Bytes data = readFor(fd, 13 * 20, 10.0);
  const auto frames = scanFrames(data);
  ASSERT_GE(frames.size(), 10u);
  for (const Frame& f : frames)
  {
    ASSERT_EQ(f.payload.size(), 10u);
    EXPECT_EQ(f.payload[0], 7);
    EXPECT_EQ(f.payload[2], 19);
    EXPECT_EQ(f.payload[5], 20);
    EXPECT_EQ(f.payload[8], 35);
    EXPECT_EQ(f.payload[9], 2);  // Safe
  }
  // Pause the stream, drive 100 mm/s straight, ask for distance with Sensors.
  writeAll(fd, { 150, 0, 137, 0, 100, 0x80, 0x00 });
  {
    // Wait until the robot moved, without a fixed sleep.
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < end)
    {
      {
        std::lock_guard<std::mutex> lock(sim.mutex);
        if (sim.robot.truePose().x > 0.02)
          break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  writeAll(fd, { 137, 0, 0, 0x80, 0x00 });
  ::tcflush(fd, TCIFLUSH);  // drop frames still in flight from before the pause
  readFor(fd, 1000, 0.1);
  writeAll(fd, { 149, 2, 35, 39 });  // Query List: mode, requested velocity
  const Bytes reply = readFor(fd, 3, 10.0);
  ASSERT_EQ(reply.size(), 3u);
  EXPECT_EQ(reply[0], 2);
  EXPECT_EQ(reply[1], 0);
  EXPECT_EQ(reply[2], 0);
  {
    std::lock_guard<std::mutex> lock(sim.mutex);
    EXPECT_GT(sim.robot.truePose().x, 0.02);
  }
  ::close(fd);
}

TEST(Pty, ClosingThePtyGivesClientsEof)
{
  const std::string link = tempLink("close");
  cd::Pty pty;
  std::string err;
  ASSERT_TRUE(pty.open(&err) && pty.link(link, &err)) << err;
  const int fd = openClient(link);
  ASSERT_GE(fd, 0);
  const uint8_t b = 0x42;
  EXPECT_EQ(pty.write(&b, 1), 1u);
  pty.unlink();
  pty.close();
  Bytes got;
  uint8_t buf[16];
  ssize_t n = 0;
  // The byte written before the close may still be delivered; after it, EOF or EIO.
  for (int i = 0; i < 3; ++i)
  {
    pollfd p{ fd, POLLIN, 0 };
    ASSERT_GT(::poll(&p, 1, 5000), 0) << "no EOF/EIO after the pty was closed";
    n = ::read(fd, buf, sizeof(buf));
    if (n <= 0)
      break;
  }
  EXPECT_LE(n, 0);
  ::close(fd);
}

TEST(Pty, OutputIsDroppedWhileNoClientHasThePortOpen)
{
  const std::string link = tempLink("fresh");
  SimThread sim(link);
  ASSERT_TRUE(sim.ok) << sim.error;
  const int first = openClient(link);
  ASSERT_GE(first, 0);
  // Start, Safe, Stream [7, 19, 20, 35] (13-byte frames), then leave without stopping the stream.
  writeAll(first, { 128, 131, 148, 4, 7, 19, 20, 35 });
  ASSERT_GE(scanFrames(readFor(first, 13 * 10, 10.0)).size(), 5u);
  ::close(first);
  {
    // While nobody listens the robot keeps streaming; wait for enough output to fill a buffer.
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    uint64_t steps = 0;
    while (std::chrono::steady_clock::now() < end && steps < 200)
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      ++steps;
    }
  }
  // Hold the simulator still while the next client opens and looks: whatever is readable now was
  // written before it came. A real cable delivers none of that.
  int second = -1;
  int stale = -1;
  {
    std::lock_guard<std::mutex> lock(sim.mutex);
    second = ::open(link.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);  // no flush: like a careless client
    ASSERT_GE(second, 0);
    ASSERT_EQ(::ioctl(second, FIONREAD, &stale), 0);
  }
  EXPECT_EQ(stale, 0) << "the new client found " << stale << " stale bytes";
  // The stream still runs and reaches the new client.
  const auto frames = scanFrames(readFor(second, 13 * 5, 10.0));
  EXPECT_GE(frames.size(), 3u);
  EXPECT_EQ(sim.pty.clients(), 1);
  ::close(second);
}
