// The simulated camera's per-frame decisions: default poses, noise seeds, exposure stamps.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>

#include "sl_sim/camera_frames.h"

namespace sl_sim
{
namespace
{
constexpr std::int64_t kSecond = 1000000000;
constexpr std::int64_t kMs = 1000000;

TEST(CameraFrames, DefaultRobotHasItsFrontEdgeAtTheWorldOrigin)
{
  const Eigen::Isometry3d robot = defaultRobotInWorld(0.2);
  EXPECT_TRUE(robot.linear().isIdentity());
  EXPECT_TRUE((robot * Eigen::Vector3d(0.2, 0.0, 0.0)).isZero(1e-12));
}

TEST(CameraFrames, DefaultCameraSitsOnTheMountAtTheFrontEdge)
{
  sl_projector::Rig rig;
  rig.mount.xyz = Eigen::Vector3d(0.01, 0.02, 0.3);
  const Eigen::Isometry3d camera = defaultCameraInBase(rig, 0.2);
  EXPECT_NEAR(camera.translation().x(), 0.21, 1e-12);
  EXPECT_NEAR(camera.translation().y(), 0.02, 1e-12);
  EXPECT_NEAR(camera.translation().z(), 0.3, 1e-12);
  // Optical frame (REP 103): z forward along the robot's x axis, x to the robot's right.
  EXPECT_TRUE((camera.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE((camera.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  // In the world without tf the camera is at the mount above the origin.
  const Eigen::Isometry3d in_world = defaultRobotInWorld(0.2) * camera;
  EXPECT_NEAR(in_world.translation().x(), 0.01, 1e-12);
}

TEST(CameraFrames, FrameSeedsDifferPerFrameAndRepeatPerSeed)
{
  std::set<std::uint64_t> seen;
  for (int seed = 0; seed < 3; ++seed)
    for (std::uint64_t frame = 0; frame < 100; ++frame)
      EXPECT_TRUE(seen.insert(frameSeed(seed, frame)).second) << seed << " " << frame;
  EXPECT_EQ(frameSeed(7, 5), frameSeed(7, 5));
  EXPECT_EQ(frameSeed(0, 5), 5u);
}

TEST(ExposureStamper, UsesAFreshPoseTime)
{
  ExposureStamper s;
  EXPECT_EQ(s.stamp(100 * kSecond - 50 * kMs, 100 * kSecond), 100 * kSecond - 50 * kMs);
  EXPECT_EQ(s.stamp(100 * kSecond, 100 * kSecond), 100 * kSecond);  // the pose of this very moment
}

TEST(ExposureStamper, UsesNowWithoutPoseOrForAStaleOrFuturePose)
{
  ExposureStamper s;
  EXPECT_EQ(s.stamp(0, 10 * kSecond), 10 * kSecond);  // no pose (tf missing, use_tf false)
  EXPECT_EQ(s.stamp(20 * kSecond - ExposureStamper::kMaxPoseAge - 1, 20 * kSecond), 20 * kSecond);
  EXPECT_EQ(s.stamp(20 * kSecond - ExposureStamper::kMaxPoseAge, 20 * kSecond + 0), 20 * kSecond);  // not newer
  ExposureStamper t;
  EXPECT_EQ(t.stamp(30 * kSecond - ExposureStamper::kMaxPoseAge, 30 * kSecond),
            30 * kSecond - ExposureStamper::kMaxPoseAge);              // exactly at the age limit
  EXPECT_EQ(t.stamp(31 * kSecond + kMs, 31 * kSecond), 31 * kSecond);  // a pose from the future
}

TEST(ExposureStamper, NeverRepeatsOrGoesBackWithTheSamePose)
{
  ExposureStamper s;
  const std::int64_t pose = 50 * kSecond;
  EXPECT_EQ(s.stamp(pose, pose + 10 * kMs), pose);
  // The same pose again (tf not updated): now instead, so that two images never share a stamp.
  EXPECT_EQ(s.stamp(pose, pose + 20 * kMs), pose + 20 * kMs);
  // A newer pose, but older than the last stamp given: now again.
  EXPECT_EQ(s.stamp(pose + 15 * kMs, pose + 30 * kMs), pose + 30 * kMs);
  EXPECT_EQ(s.stamp(pose + 40 * kMs, pose + 45 * kMs), pose + 40 * kMs);
}
}  // namespace
}  // namespace sl_sim
