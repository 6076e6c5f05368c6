/**
 * @file
 * Holds a player at its first frame until someone wants its images.
 */
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace sl_camera
{

/**
 * A one-way gate shared between the thread that decides when playback starts (the nodelet, on
 * the first subscription) and the capture thread that waits for it. Once opened it stays open.
 * Thread-safe.
 */
class StartGate
{
public:
  /** @param open start out open (playback not held) */
  explicit StartGate(bool open = false) : open_(open) {}

  /** Opens the gate and wakes a waiting grab. Idempotent. */
  void open();

  /** True once open() was called (or the gate was created open). */
  bool isOpen() const;

  /**
   * Waits until the gate is open, at most @p timeout.
   * @return isOpen()
   */
  bool waitFor(std::chrono::milliseconds timeout) const;

private:
  mutable std::mutex mutex_;
  mutable std::condition_variable opened_;
  bool open_;
};

/**
 * When a held player should start, from the subscriber counts of its image and camera_info topics.
 * A camera subscriber (image and camera_info, paired) starts it once both topics are connected:
 * otherwise frame 0's camera_info could go out before its connection exists and frame 0 could not
 * be paired. A subscriber of the image alone starts it once the image has had a subscriber for
 * @p image_only_grace without one on camera_info.
 * @param image_subscribers subscribers of the image (any transport)
 * @param info_subscribers subscribers of camera_info
 * @param image_only_for how long the image has had a subscriber, s (0 when it has none)
 * @param image_only_grace see above, s (>= 0)
 */
bool shouldStartPlayback(int image_subscribers, int info_subscribers, double image_only_for, double image_only_grace);

/**
 * Keeps the time since the image topic got its subscriber and decides with shouldStartPlayback()
 * when a held player starts. Not thread-safe: the owner guards it.
 */
class PlaybackStarter
{
public:
  /** @param image_only_grace see shouldStartPlayback(), s (>= 0) */
  explicit PlaybackStarter(double image_only_grace) : image_only_grace_(image_only_grace) {}

  /**
   * The subscriber counts at @p now (seconds of any one clock).
   * @return true when playback is to start
   */
  bool update(int image_subscribers, int info_subscribers, double now);

private:
  double image_only_grace_;
  bool image_subscribed_ = false;
  double image_subscribed_since_ = 0.0;
};

}  // namespace sl_camera
