#include "sl_sim/camera_frames.h"

#include <algorithm>

#include "sl_sim/renderer.h"

namespace sl_sim
{
namespace
{
Eigen::Isometry3d translationX(double x)
{
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation().x() = x;
  return t;
}
}  // namespace

Eigen::Isometry3d defaultRobotInWorld(double robot_radius)
{
  return translationX(-robot_radius);
}

Eigen::Isometry3d defaultCameraInBase(const sl_projector::Rig& rig, double robot_radius)
{
  return translationX(robot_radius) * toIsometry(rig.mount.cameraOpticalInParent());
}

std::uint64_t frameSeed(int seed, std::uint64_t frame)
{
  return static_cast<std::uint64_t>(seed) * 0x100000001ULL + frame;
}

std::int64_t ExposureStamper::stamp(std::int64_t pose_ns, std::int64_t now_ns)
{
  std::int64_t stamp = now_ns;
  if (pose_ns != 0 && pose_ns <= now_ns && now_ns - pose_ns <= kMaxPoseAge && pose_ns > last_)
    stamp = pose_ns;
  last_ = std::max(last_, stamp);
  return stamp;
}

}  // namespace sl_sim
