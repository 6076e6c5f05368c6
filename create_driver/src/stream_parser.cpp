#include "create_driver/stream_parser.h"

#include <algorithm>

namespace create_driver
{
namespace
{
constexpr size_t kChunk = 256;     // bytes appended per processing round (bounds the buffer)
constexpr size_t kMinPayload = 2;  // one id and at least one data byte
}  // namespace

StreamParser::StreamParser(Model model) : model_(model)
{
  buf_.reserve(1024);
  updates_.reserve(16);
}

void StreamParser::setExpectedIds(const std::vector<uint8_t>& ids)
{
  expected_ids_ = ids;
  expected_len_ = 0;
  for (uint8_t id : ids)
    expected_len_ += 1 + packetSize(id, model_);
}

size_t StreamParser::feed(const uint8_t* data, size_t len)
{
  updates_.clear();
  size_t offset = 0;
  while (offset < len)
  {
    const size_t n = std::min(kChunk, len - offset);
    if (start_ > 0 && buf_.size() + n > buf_.capacity())
    {
      buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(start_));
      start_ = 0;
    }
    buf_.insert(buf_.end(), data + offset, data + offset + n);
    offset += n;
    process();
  }
  if (start_ == buf_.size())
  {
    buf_.clear();
    start_ = 0;
  }
  return updates_.size();
}

bool StreamParser::plausibleLength(uint8_t n) const
{
  if (!expected_ids_.empty())
    return n == expected_len_;
  return n >= kMinPayload;
}

void StreamParser::discard(size_t count)
{
  if (synced_)
  {
    ++counters_.resyncs;
    synced_ = false;
  }
  start_ += count;
}

void StreamParser::process()
{
  while (start_ < buf_.size())
  {
    const size_t avail = buf_.size() - start_;
    const uint8_t* p = buf_.data() + start_;
    if (p[0] != oi::STREAM_HEADER)
    {
      // Skip to the next candidate header.
      const uint8_t* next = std::find(p, p + avail, oi::STREAM_HEADER);
      const auto skipped = static_cast<size_t>(next - p);
      counters_.discarded_bytes += skipped;
      discard(skipped);
      continue;
    }
    if (avail < 2)
      return;
    const uint8_t n = p[1];
    bool reject = !plausibleLength(n);
    if (!reject && avail >= 3)
    {
      // Early structural check on the first id, so a false header is dropped without waiting for
      // a whole (possibly long) bogus frame.
      reject = expected_ids_.empty() ? !isValidPacket(p[2], model_) : p[2] != expected_ids_[0];
    }
    if (reject)
    {
      // A data byte that looked like a header: not a frame.
      ++counters_.discarded_bytes;
      discard(1);
      continue;
    }
    const size_t frame_len = static_cast<size_t>(n) + 3;
    if (avail < frame_len)
      return;
    uint8_t sum = 0;
    for (size_t i = 0; i < frame_len; ++i)
      sum = static_cast<uint8_t>(sum + p[i]);
    if (sum == 0 && parseFrame(p + 2, n))
    {
      committed_ = staging_;
      updates_.push_back(committed_);
      ++counters_.valid_frames;
      synced_ = true;
      start_ += frame_len;
    }
    else
    {
      ++counters_.corrupt_frames;
      ++counters_.discarded_bytes;
      discard(1);
    }
  }
}

bool StreamParser::parseFrame(const uint8_t* payload, size_t n)
{
  staging_ = committed_;
  staging_.present = 0;
  size_t i = 0;
  size_t k = 0;
  while (i < n)
  {
    const uint8_t id = payload[i++];
    if (!expected_ids_.empty() && (k >= expected_ids_.size() || expected_ids_[k] != id))
      return false;
    ++k;
    const size_t size = packetSize(id, model_);
    if (size == 0 || i + size > n)
      return false;
    decodePacket(id, payload + i, model_, staging_);
    i += size;
  }
  return expected_ids_.empty() || k == expected_ids_.size();
}

void StreamParser::clearBuffer()
{
  buf_.clear();
  start_ = 0;
  synced_ = false;
}

void StreamParser::reset()
{
  clearBuffer();
  committed_ = SensorState();
  staging_ = SensorState();
  updates_.clear();
  counters_ = ParserCounters();
}

ReplyParser::ReplyParser(Model model) : model_(model) {}

bool ReplyParser::expect(const std::vector<uint8_t>& ids)
{
  ids_.clear();
  buf_.clear();
  complete_ = false;
  expected_len_ = 0;
  for (uint8_t id : ids)
  {
    const size_t s = packetSize(id, model_);
    if (s == 0)
    {
      ids_.clear();
      expected_len_ = 0;
      return false;
    }
    expected_len_ += s;
  }
  ids_ = ids;
  buf_.reserve(expected_len_);
  return true;
}

size_t ReplyParser::feed(const uint8_t* data, size_t len)
{
  if (complete_ || ids_.empty())
    return 0;
  const size_t take = std::min(len, expected_len_ - buf_.size());
  buf_.insert(buf_.end(), data, data + take);
  if (buf_.size() == expected_len_)
  {
    state_.present = 0;
    size_t offset = 0;
    for (uint8_t id : ids_)
    {
      decodePacket(id, buf_.data() + offset, model_, state_);
      offset += packetSize(id, model_);
    }
    complete_ = true;
  }
  return take;
}

uint8_t streamChecksum(const uint8_t* data, size_t len)
{
  uint8_t sum = 0;
  for (size_t i = 0; i < len; ++i)
    sum = static_cast<uint8_t>(sum + data[i]);
  return static_cast<uint8_t>(0x100 - sum);
}

void appendStreamFrame(Bytes& out, const std::vector<uint8_t>& ids, const SensorState& state, Model model)
{
  const size_t begin = out.size();
  out.push_back(oi::STREAM_HEADER);
  out.push_back(0);
  for (uint8_t id : ids)
  {
    if (!isValidPacket(id, model))
      continue;
    out.push_back(id);
    encodePacket(id, state, model, out);
  }
  out[begin + 1] = static_cast<uint8_t>(out.size() - begin - 2);
  out.push_back(streamChecksum(out.data() + begin, out.size() - begin));
}

}  // namespace create_driver
