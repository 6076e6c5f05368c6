/// @file fuzz_input.h
/// @brief Helpers shared by the fuzz targets: a front-to-back reader of the fuzz input and a check
/// that aborts (so libFuzzer keeps the input as a crash) when a documented property does not hold.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

/// Aborts with the failed condition: libFuzzer reports it as a crash with its reproducer.
#define FUZZ_CHECK(condition)                                                                  \
  do                                                                                           \
  {                                                                                            \
    if (!(condition))                                                                          \
    {                                                                                          \
      std::fprintf(stderr, "FUZZ_CHECK failed: %s (%s:%d)\n", #condition, __FILE__, __LINE__); \
      std::abort();                                                                            \
    }                                                                                          \
  } while (false)

namespace sl_fuzz
{
/// @brief Reads the fuzz input from the front. Reads past the end give zeros, so every input is
/// a complete (if short) recipe; the seed generator (make_seeds.py) writes the same layout.
class FuzzInput
{
public:
  FuzzInput(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  /// @brief Bytes not read yet.
  size_t remaining() const { return size_ - pos_; }
  /// @brief True when everything was read.
  bool empty() const { return pos_ >= size_; }

  uint8_t u8() { return pos_ < size_ ? data_[pos_++] : 0; }
  /// @brief Little-endian.
  uint16_t u16()
  {
    const uint16_t lo = u8();
    return static_cast<uint16_t>(lo | (u8() << 8));
  }
  /// @brief Little-endian.
  uint32_t u32()
  {
    const uint32_t lo = u16();
    return lo | (static_cast<uint32_t>(u16()) << 16);
  }
  /// @brief u8() mapped to [lo, hi].
  double range(double lo, double hi) { return lo + (hi - lo) * u8() / 255.0; }

  /// @brief Up to @p n bytes (fewer at the end of the input).
  std::vector<uint8_t> bytes(size_t n)
  {
    n = n < remaining() ? n : remaining();
    std::vector<uint8_t> out(data_ + pos_, data_ + pos_ + n);
    pos_ += n;
    return out;
  }
  /// @brief Everything not read yet.
  std::vector<uint8_t> rest() { return bytes(remaining()); }
  /// @brief Pointer to the unread bytes (valid while the input lives).
  const uint8_t* current() const { return data_ + pos_; }

private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

/// @brief A small deterministic generator (64-bit LCG) for choices that must not cost input bytes.
class Lcg
{
public:
  explicit Lcg(uint64_t seed) : state_(seed * 2862933555777941757ULL + 3037000493ULL) {}
  uint32_t next()
  {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<uint32_t>(state_ >> 33);
  }

private:
  uint64_t state_;
};

/// @brief FNV-1a of the input: a seed derived from all of it.
inline uint64_t hashBytes(const uint8_t* data, size_t size)
{
  uint64_t h = 1469598103934665603ULL;
  for (size_t i = 0; i < size; ++i)
    h = (h ^ data[i]) * 1099511628211ULL;
  return h;
}
}  // namespace sl_fuzz
