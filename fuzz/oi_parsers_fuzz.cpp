// Fuzz target: create_driver's Open Interface parsers (StreamParser, ReplyParser) on arbitrary bytes.
//
// Input: [flags] [n] [n packet ids] [bytes from the robot ...]
//   flags bit 0: Create 2 packet table; bit 1: the stream parser expects exactly the ids.
// Besides the sanitizers it checks what the headers promise:
//  - the stream parser is a pure function of the bytes: all at once, byte by byte and in uneven
//    chunks it commits the same frames and counts the same;
//  - a reply parser consumes exactly the expected length and nothing after it;
//  - a reply re-sent as a stream frame (appendStreamFrame) parses back to the same values.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "create_driver/stream_parser.h"
#include "fuzz_input.h"

namespace
{
using create_driver::Bytes;
using create_driver::Model;
using create_driver::ParserCounters;
using create_driver::ReplyParser;
using create_driver::SensorState;
using create_driver::StreamParser;

struct Trace
{
  std::vector<SensorState> updates;
  ParserCounters counters;
  size_t buffered = 0;
};

enum class Chunks
{
  All,
  Single,
  Uneven
};

bool sameState(const SensorState& a, const SensorState& b)
{
  return a.value == b.value && a.present == b.present;
}

bool sameCounters(const ParserCounters& a, const ParserCounters& b)
{
  return a.valid_frames == b.valid_frames && a.corrupt_frames == b.corrupt_frames && a.resyncs == b.resyncs &&
         a.discarded_bytes == b.discarded_bytes;
}

Trace runStream(Model model, const std::vector<uint8_t>* expected, const uint8_t* data, size_t len, Chunks chunks)
{
  StreamParser parser(model);
  if (expected)
    parser.setExpectedIds(*expected);
  Trace trace;
  sl_fuzz::Lcg lcg(len);
  size_t offset = 0;
  while (offset < len)
  {
    size_t n = len - offset;
    if (chunks == Chunks::Single)
      n = 1;
    else if (chunks == Chunks::Uneven)
      n = std::min<size_t>(n, 1 + lcg.next() % 300);  // across the parser's 256-byte rounds too
    const size_t committed = parser.feed(data + offset, n);
    FUZZ_CHECK(committed == parser.updates().size());
    trace.updates.insert(trace.updates.end(), parser.updates().begin(), parser.updates().end());
    if (committed > 0)
      FUZZ_CHECK(sameState(parser.state(), parser.updates().back()));
    offset += n;
  }
  trace.counters = parser.counters();
  trace.buffered = parser.buffered();
  FUZZ_CHECK(trace.counters.valid_frames == trace.updates.size());
  parser.clearBuffer();
  FUZZ_CHECK(parser.buffered() == 0);
  return trace;
}

void checkStream(Model model, const std::vector<uint8_t>* expected, const uint8_t* data, size_t len)
{
  const Trace all = runStream(model, expected, data, len, Chunks::All);
  for (Chunks chunks : { Chunks::Single, Chunks::Uneven })
  {
    const Trace other = runStream(model, expected, data, len, chunks);
    FUZZ_CHECK(other.updates.size() == all.updates.size());
    for (size_t i = 0; i < all.updates.size(); ++i)
      FUZZ_CHECK(sameState(other.updates[i], all.updates[i]));
    FUZZ_CHECK(sameCounters(other.counters, all.counters));
    FUZZ_CHECK(other.buffered == all.buffered);
  }
}

void checkReply(Model model, const std::vector<uint8_t>& ids, const uint8_t* data, size_t len)
{
  ReplyParser reply(model);
  const bool known = reply.expect(ids);
  size_t expected_len = 0;
  for (uint8_t id : ids)
    expected_len += create_driver::packetSize(id, model);
  if (!known || ids.empty())
  {
    FUZZ_CHECK(reply.feed(data, len) == 0);
    FUZZ_CHECK(!reply.complete());
    return;
  }
  FUZZ_CHECK(reply.expectedLength() == expected_len);
  size_t consumed = 0;
  sl_fuzz::Lcg lcg(len + 7);
  size_t offset = 0;
  while (offset < len)
  {
    const size_t n = std::min<size_t>(len - offset, 1 + lcg.next() % 40);
    const size_t took = reply.feed(data + offset, n);
    FUZZ_CHECK(took <= n);
    consumed += took;
    offset += n;
  }
  FUZZ_CHECK(consumed == std::min(len, expected_len));
  FUZZ_CHECK(reply.complete() == (len >= expected_len));
  if (!reply.complete())
    return;
  FUZZ_CHECK(reply.feed(data, len) == 0);

  // The same values as a stream frame. The frame's length byte counts ids and data: only a
  // payload of at most 255 bytes can be framed.
  if (ids.size() + expected_len > 255 || ids.size() + expected_len < 2)
    return;
  Bytes frame;
  create_driver::appendStreamFrame(frame, ids, reply.state(), model);
  StreamParser stream(model);
  stream.setExpectedIds(ids);
  FUZZ_CHECK(stream.feed(frame.data(), frame.size()) == 1);
  const SensorState& s = stream.state();
  for (uint8_t id = 0; id <= create_driver::packet::MAX_SINGLE_ID; ++id)
  {
    FUZZ_CHECK(s.has(id) == reply.state().has(id));
    if (s.has(id))
      FUZZ_CHECK(s.get(id) == reply.state().get(id));
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  sl_fuzz::FuzzInput in(data, size);
  const uint8_t flags = in.u8();
  const Model model = (flags & 1) ? Model::CREATE_2 : Model::CREATE_1;
  const std::vector<uint8_t> ids = in.bytes(in.u8());
  const uint8_t* rest = in.current();
  const size_t len = in.remaining();
  checkStream(model, (flags & 2) ? &ids : nullptr, rest, len);
  checkReply(model, ids, rest, len);
  return 0;
}
