#include "sl_decoder/decoder_stats.h"

namespace sl_decoder
{

void DecoderStats::recordFrame(const DecodeResult& result)
{
  last_blobs = static_cast<int>(result.blobs.size());
  last_decoded = result.decoded;
  last_valid = result.valid;
  last_ms = result.times.total;
  ++frames;
}

double DecoderStats::validFraction() const
{
  return last_blobs > 0 ? static_cast<double>(last_valid) / last_blobs : 0.0;
}

DecoderStats::Level DecoderStats::level() const
{
  return frames > 0 && last_valid == 0 ? Level::Warn : Level::Ok;
}

std::string DecoderStats::summary() const
{
  if (frames == 0)
    return "no image decoded yet (idle until someone subscribes)";
  if (last_valid == 0)
    return "no points in the last image";
  return "decoding";
}

}  // namespace sl_decoder
