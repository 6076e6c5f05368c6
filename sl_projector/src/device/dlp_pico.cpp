#include "device/dlp_pico.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <sys/ioctl.h>
#include <unistd.h>

namespace sl_projector
{

std::vector<uint8_t> I2cWrite::bytes() const
{
  return { sub_address, static_cast<uint8_t>(data >> 24), static_cast<uint8_t>(data >> 16),
           static_cast<uint8_t>(data >> 8), static_cast<uint8_t>(data) };
}

std::vector<I2cWrite> dlpPicoSetup(bool flip, bool crop)
{
  std::vector<I2cWrite> writes;
  if (flip)
  {
    writes.push_back({ 0x08, 0x00000000u });  // long-axis flip
    writes.push_back({ 0x09, 0x00000000u });  // short-axis flip
  }
  if (crop)
    writes.push_back({ 0x05, 0x00000007u });  // display mode: crop, no scaling
  return writes;
}

std::string formatWrites(uint8_t device_address, const std::vector<I2cWrite>& writes)
{
  std::string out;
  char buf[16];
  for (const I2cWrite& w : writes)
  {
    std::snprintf(buf, sizeof(buf), "addr 0x%02x:", device_address);
    out += buf;
    for (uint8_t b : w.bytes())
    {
      std::snprintf(buf, sizeof(buf), " %02x", b);
      out += buf;
    }
    out += "\n";
  }
  return out;
}

void sendI2cWrites(const std::string& bus_path, uint8_t device_address, const std::vector<I2cWrite>& writes)
{
  const int fd = ::open(bus_path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0)
    throw std::runtime_error("cannot open I2C bus " + bus_path + ": " + std::strerror(errno) +
                             " (is i2c-dev loaded and the user in group i2c?)");
  struct Closer
  {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{ fd };
  if (::ioctl(fd, I2C_SLAVE, device_address) < 0)
    throw std::runtime_error("cannot select I2C device address on " + bus_path + ": " + std::strerror(errno));
  for (const I2cWrite& w : writes)
  {
    const std::vector<uint8_t> bytes = w.bytes();
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n != static_cast<ssize_t>(bytes.size()))
      throw std::runtime_error("I2C write to sub-address " + std::to_string(w.sub_address) + " on " + bus_path +
                               " failed: " + (n < 0 ? std::strerror(errno) : "short write"));
  }
}

}  // namespace sl_projector
