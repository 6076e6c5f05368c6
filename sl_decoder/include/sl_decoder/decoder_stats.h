#pragma once
/// @file decoder_stats.h
/// @brief What the decoder node reports about its work: counts and the last frame's figures (ROS-free).

#include <array>
#include <string>

#include "sl_decoder/decoder.h"
#include "sl_decoder/ray_classifier.h"

namespace sl_decoder
{

/**
 * @brief Counters of a decoding node and the figures of its last decoded frame, with the summary
 * its diagnostics show. Not thread-safe: the owner guards it.
 */
struct DecoderStats
{
  /// @brief Level of the summary.
  enum class Level
  {
    Ok,
    Warn
  };

  long frames = 0;                          ///< images decoded
  long rejected = 0;                        ///< images dropped (encoding, size)
  long tf_failures = 0;                     ///< frames without a transform to the target frame
  long tf_latest = 0;                       ///< frames located with the newest transform (none at the image time yet)
  double tf_age = 0.0;                      ///< age of the newest transform used, s
  int last_blobs = 0;                       ///< blobs of the last decoded image
  int last_decoded = 0;                     ///< decoded blobs of the last image
  int last_valid = 0;                       ///< blobs with a 3D point in the last image
  double last_ms = 0.0;                     ///< processing time of the last image, ms
  std::array<int, kRayStates> last_rays{};  ///< ray outcomes of the last classified frame, per RayState

  /// @brief Counts a decoded image and keeps its figures.
  void recordFrame(const DecodeResult& result);

  /// @brief Valid points per blob of the last image (0 without blobs).
  double validFraction() const;

  /// @brief OK while idle or decoding points, WARN when the last image gave none.
  Level level() const;

  /// @brief One line for the level: idle, no points, or decoding.
  std::string summary() const;
};

}  // namespace sl_decoder
