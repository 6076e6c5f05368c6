// EpipolarIndex on the default rig, by its geometry alone (no rendering): every primitive is a
// candidate wherever its ray can appear, and the camera and projector rays agree with the rig model
// (the lists by shape: decoder_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "sl_decoder/decoder_config.h"
#include "sl_decoder/epipolar_index.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"

using namespace sl_decoder;

namespace
{
const sl_projector::Rig& rig()
{
  static const sl_projector::Rig r = sl_projector::loadRig(SL_PROJECTOR_CONFIG_DIR "/default_rig.yaml");
  return r;
}

/// The camera pixel of primitive (row, col)'s projector ray at camera depth @p z.
Eigen::Vector2d pixelAt(const sl_projector::Pattern& pattern, int row, int col, double z)
{
  const cv::Point2d c = pattern.primitiveCentroid(row, col);
  Eigen::Vector3d origin, direction;
  rig().projectorRay(Eigen::Vector2d(c.x, c.y), origin, direction);
  return rig().camera.project(origin + ((z - origin.z()) / direction.z()) * direction);
}

bool contains(const int32_t* begin, const int32_t* end, int32_t value)
{
  return std::find(begin, end, value) != end;
}
}  // namespace

TEST(EpipolarIndex, EveryPrimitiveIsACandidateAlongItsWholeSegment)
{
  const DecoderConfig config;
  const EpipolarIndex index(rig(), config);
  const sl_projector::Pattern pattern(rig().pattern);
  const int rows = rig().pattern.rows, cols = rig().pattern.cols;
  int checked = 0;
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col)
      for (double z = config.min_depth; z <= config.max_depth; z += 0.05)
      {
        const Eigen::Vector2d q = pixelAt(pattern, row, col, z);
        if (!rig().camera.inImage(q))
          continue;
        const int32_t id = row * cols + col;
        const int32_t *begin, *end;
        index.candidates(static_cast<float>(q.x()), static_cast<float>(q.y()), begin, end);
        ASSERT_TRUE(contains(begin, end, id)) << "primitive " << row << "," << col << " at z " << z;
        index.candidates(static_cast<float>(q.x()), static_cast<float>(q.y()), pattern.array().value(row, col), begin,
                         end);
        ASSERT_TRUE(contains(begin, end, id)) << "primitive " << row << "," << col << " at z " << z << " by shape";
        ++checked;
      }
  EXPECT_GT(checked, rows * cols * 10) << "most segments lie in the image";
}

TEST(EpipolarIndex, CameraRaysInvertTheProjection)
{
  const EpipolarIndex index(rig(), DecoderConfig());
  double worst = 0.0;
  for (int v = 2; v < rig().camera.height - 2; v += 23)
    for (int u = 2; u < rig().camera.width - 2; u += 29)
    {
      const Eigen::Vector3d ray = index.cameraRay(u + 0.25, v + 0.5);
      EXPECT_DOUBLE_EQ(ray.z(), 1.0);
      const Eigen::Vector2d back = rig().camera.project(0.8 * ray);
      worst = std::max(worst, (back - Eigen::Vector2d(u + 0.25, v + 0.5)).norm());
    }
  std::printf("[ MEASURED ] camera ray round trip: worst %.4f px\n", worst);
  EXPECT_LT(worst, 0.0004) << "measured 0.0002 px: the undistortion table is bilinear on a fine grid";
}

TEST(EpipolarIndex, ProjectorRaysAreTheRigsUnitDirections)
{
  const EpipolarIndex index(rig(), DecoderConfig());
  const sl_projector::Pattern pattern(rig().pattern);
  const int cols = rig().pattern.cols;
  for (int id = 0; id < rig().pattern.rows * cols; id += 7)
  {
    const cv::Point2d c = pattern.primitiveCentroid(id / cols, id % cols);
    Eigen::Vector3d origin, direction;
    rig().projectorRay(Eigen::Vector2d(c.x, c.y), origin, direction);
    EXPECT_NEAR(index.projectorDirection(id).norm(), 1.0, 1e-9) << id;
    EXPECT_NEAR((index.projectorDirection(id) - direction.normalized()).norm(), 0.0, 1e-6) << id;
    EXPECT_NEAR((index.projectorOrigin() - origin).norm(), 0.0, 1e-9) << id;
  }
}
