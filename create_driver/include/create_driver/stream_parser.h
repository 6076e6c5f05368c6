/// @file stream_parser.h
/// @brief Parsers for Open Interface sensor data: the checksummed Stream frames and the plain
/// replies to Sensors / Query List.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "create_driver/sensor_packets.h"

namespace create_driver
{
/// Counters of a StreamParser.
struct ParserCounters
{
  uint64_t valid_frames = 0;     ///< frames whose checksum and structure held (committed)
  uint64_t corrupt_frames = 0;   ///< complete candidate frames rejected (bad checksum or packet ids)
  uint64_t resyncs = 0;          ///< times the parser lost synchronisation after having had it
  uint64_t discarded_bytes = 0;  ///< bytes skipped while looking for a frame header
  /// @brief Valid plus corrupt frames.
  uint64_t totalFrames() const { return valid_frames + corrupt_frames; }
};

/// @brief Incremental parser of Stream frames: [19][n][id][data]...[id][data][checksum].
///
/// The parser is a pure function of the bytes fed to it (no clock). A frame is accepted when the
/// sum of all its bytes, header and checksum included, is 0 mod 256 and its payload is an exact
/// sequence of known packet ids with their data (and, if expected ids were set, exactly those ids
/// in that order). Values are decoded into a staging copy and committed only then. After a
/// rejected candidate the search restarts one byte after its header, so a lost or extra byte, or
/// a data byte equal to 19, costs at most the frames it touched.
class StreamParser
{
public:
  /// @brief Creates a parser for the packet table of @p model.
  explicit StreamParser(Model model = Model::CREATE_1);

  /// @brief Requires frames to carry exactly these packet ids in this order (the list sent with
  /// Stream). An empty list accepts any well-formed frame.
  void setExpectedIds(const std::vector<uint8_t>& ids);

  /// @brief Feeds bytes; decodes every frame completed by them.
  /// @return the number of frames committed by this call; their states are in updates().
  size_t feed(const uint8_t* data, size_t len);

  /// @brief States committed by the last feed() call, oldest first. Each is the full state after
  /// that frame, with @c present marking the packets of that frame only.
  const std::vector<SensorState>& updates() const { return updates_; }

  /// @brief The latest committed state.
  const SensorState& state() const { return committed_; }

  /// @brief Counters since construction or reset().
  const ParserCounters& counters() const { return counters_; }

  /// @brief Drops buffered bytes and sync (e.g. after reconnecting); keeps the counters.
  void clearBuffer();

  /// @brief Drops buffered bytes, committed state and counters.
  void reset();

  /// @brief Bytes currently buffered (an incomplete frame or a candidate header).
  size_t buffered() const { return buf_.size() - start_; }

private:
  void process();
  bool plausibleLength(uint8_t n) const;
  bool parseFrame(const uint8_t* frame, size_t n);
  void discard(size_t count);

  Model model_;
  std::vector<uint8_t> expected_ids_;
  size_t expected_len_ = 0;
  std::vector<uint8_t> buf_;
  size_t start_ = 0;
  bool synced_ = false;
  SensorState committed_;
  SensorState staging_;
  std::vector<SensorState> updates_;
  ParserCounters counters_;
};

/// @brief Parser of the reply to Sensors [142] or Query List [149]: the data of the requested
/// packets concatenated, without ids or checksum, so only the length can be checked. The caller
/// must apply a timeout and call expect() again before the next request.
class ReplyParser
{
public:
  /// @brief Creates a parser for the packet table of @p model.
  explicit ReplyParser(Model model = Model::CREATE_1);

  /// @brief Starts waiting for the reply to a request of these packet ids.
  /// @return false if an id is unknown on the model (nothing is expected then)
  bool expect(const std::vector<uint8_t>& ids);

  /// @brief Feeds bytes.
  /// @return the number of bytes consumed; bytes after a complete reply are not consumed.
  size_t feed(const uint8_t* data, size_t len);

  /// @brief True once the whole reply was received and decoded into state().
  bool complete() const { return complete_; }

  /// @brief Expected reply length in bytes.
  size_t expectedLength() const { return expected_len_; }

  /// @brief Decoded state (valid when complete()).
  const SensorState& state() const { return state_; }

private:
  Model model_;
  std::vector<uint8_t> ids_;
  size_t expected_len_ = 0;
  std::vector<uint8_t> buf_;
  bool complete_ = false;
  SensorState state_;
};

/// @brief Checksum byte that makes the sum of @p data plus the checksum 0 mod 256.
uint8_t streamChecksum(const uint8_t* data, size_t len);

/// @brief Appends a complete stream frame [19][n][id data...][checksum] for @p ids.
void appendStreamFrame(Bytes& out, const std::vector<uint8_t>& ids, const SensorState& state, Model model);

}  // namespace create_driver
