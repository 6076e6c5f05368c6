/// @file cloud_pairing.h
/// @brief Pairs each image's ray ends with its decoded points, which come on another topic and in
/// either order, so that the rays go into the map after the stop check on the points (ROS-free).
#pragma once

#include <optional>
#include <utility>

namespace sl_obstacle
{
/**
 * @brief The pairing of the decoder's two clouds of one image (ray ends and points, same stamp).
 *
 * The points of an image are checked for a stop first; its ray ends then go into the map together
 * with those points (the rays that reached a surface). Ray ends that come before their points wait,
 * one image at most: when newer ray ends or points arrive, the waiting ones go in (alone when their
 * points never came: gated or dropped). @p Cloud is any copyable handle (a shared pointer); @p Stamp
 * is ordered by operator<.
 */
template <typename Cloud, typename Stamp>
class CloudPairing
{
public:
  /// Ray ends to insert now, with the points of the same image when they came.
  struct Insert
  {
    Cloud rays;
    std::optional<Cloud> points;
  };

  /**
   * @brief New points of the image at @p stamp (after their stop check).
   * @return the waiting ray ends of this or an older image, to insert now (with these points when
   *         the stamps are equal), or nothing.
   */
  std::optional<Insert> onPoints(const Cloud& points, const Stamp& stamp)
  {
    points_ = std::make_pair(points, stamp);
    if (!pending_ || stamp < pending_->second)
      return std::nullopt;
    Insert out{ pending_->first, std::nullopt };
    if (!(pending_->second < stamp))
      out.points = points;
    pending_.reset();
    return out;
  }

  /**
   * @brief New ray ends of the image at @p stamp.
   * @param[out] older ray ends that waited for points that never came, to insert first (alone)
   * @return these ray ends to insert now (with their points when they came first), or nothing when
   *         they wait for their points.
   */
  std::optional<Insert> onRays(const Cloud& rays, const Stamp& stamp, std::optional<Cloud>& older)
  {
    older.reset();
    if (!points_ || points_->second < stamp)
    {
      if (pending_)
        older = pending_->first;
      pending_ = std::make_pair(rays, stamp);
      return std::nullopt;
    }
    Insert out{ rays, std::nullopt };
    if (!(stamp < points_->second))
      out.points = points_->first;
    return out;
  }

  /// True while ray ends wait for their points.
  bool waiting() const { return pending_.has_value(); }

private:
  std::optional<std::pair<Cloud, Stamp>> points_;   // the newest points
  std::optional<std::pair<Cloud, Stamp>> pending_;  // ray ends that came before their points
};
}  // namespace sl_obstacle
