// RayClassifier on synthetic images (no rendering; the rendered scenes are sl_evaluation's): what
// no light, light everywhere and one bright spot on a segment say about each ray, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "sl_decoder/decoder.h"
#include "sl_decoder/ray_classifier.h"
#include "sl_rig/rig.h"

using namespace sl_decoder;

namespace
{
const sl_projector::Rig& rig()
{
  static const sl_projector::Rig r = sl_projector::loadRig(SL_PROJECTOR_CONFIG_DIR "/default_rig.yaml");
  return r;
}

struct Classified
{
  std::vector<RayOutcome> outcomes;
  std::array<int, kRayStates> counts{};
};

Classified classify(RayClassifier& rays, const cv::Mat& image)
{
  Decoder decoder(rig());
  DecodeResult result;
  decoder.decode(image, result);
  Classified c;
  rays.classify(image, result, c.outcomes);
  c.counts = rays.lastCounts();
  return c;
}

int count(const Classified& c, RayState s)
{
  return c.counts[static_cast<std::size_t>(s)];
}
}  // namespace

TEST(RayClassifier, ADarkFrameHoldsNoSurface)
{
  // No light anywhere (a little read noise): no ray is decoded, lit or floor; those in view are dark.
  RayClassifier rays(rig(), DecoderConfig(), RayConfig());
  cv::Mat image(rig().camera.height, rig().camera.width, CV_8UC1);
  cv::randn(image, 6.0, 1.5);
  const Classified c = classify(rays, image);
  EXPECT_EQ(count(c, RayState::Decoded), 0);
  EXPECT_EQ(count(c, RayState::Lit), 0);
  EXPECT_EQ(count(c, RayState::Floor), 0);
  EXPECT_GT(count(c, RayState::Dark), static_cast<int>(c.outcomes.size()) / 2);
  // A dark ray is checked as far as it stays in the image, short of the floor and of the depth where
  // a min_albedo surface would fade into the noise.
  const double checked = std::min(0.7, rays.lastDetectableDepth() - 0.02);
  int short_rays = 0;
  for (int i = 0; i < static_cast<int>(c.outcomes.size()); ++i)
  {
    const RayOutcome& o = c.outcomes[static_cast<std::size_t>(i)];
    if (o.state != RayState::Dark)
      continue;
    EXPECT_LE(o.depth, static_cast<float>(rays.config().max_range) + 1e-3F);
    const bool in_view = rig().camera.inImage(rig().camera.project(rays.pointAtDepth(i, checked).cast<double>()));
    const bool floor_before = rays.floorDepth(i) < checked;  // NaN: no floor hit in range
    short_rays += in_view && !floor_before && o.depth < checked - 0.02;
  }
  EXPECT_EQ(short_rays, 0) << "dark rays end before " << checked << " m with their segment still in view";
}

TEST(RayClassifier, SaturationIsLightAtEveryDepth)
{
  // Saturated everywhere: whatever stands in front could be there at any depth. No ray may be
  // free beyond its first sample.
  RayClassifier rays(rig(), DecoderConfig(), RayConfig());
  const cv::Mat image(rig().camera.height, rig().camera.width, CV_8UC1, cv::Scalar(255));
  const Classified c = classify(rays, image);
  EXPECT_EQ(count(c, RayState::Decoded), 0);
  EXPECT_EQ(count(c, RayState::Floor), 0);
  for (const RayOutcome& o : c.outcomes)
  {
    if (o.state == RayState::Dark || o.state == RayState::Lit)
    {
      EXPECT_LT(o.depth, 0.3F) << "a ray went through a saturated image";
    }
  }
}

TEST(RayClassifier, NoFreeRayPassesABrightSpot)
{
  // A bright disc where a horizontal band of segments crosses depth 0.6 m: every ray whose segment
  // passes under the disc ends at or before it (lit or dark up to the light), never beyond.
  RayClassifier rays(rig(), DecoderConfig(), RayConfig());
  const int cols = rig().pattern.cols, rows = rig().pattern.rows;
  const int row = rows / 2, col = cols / 2;
  const Eigen::Vector3f p = rays.pointAtDepth(row * cols + col, 0.6);
  const Eigen::Vector2d q = rig().camera.project(p.cast<double>());
  ASSERT_TRUE(rig().camera.inImage(q));
  cv::Mat image(rig().camera.height, rig().camera.width, CV_8UC1);
  cv::randn(image, 6.0, 1.5);
  cv::circle(image, cv::Point(static_cast<int>(q.x()), static_cast<int>(q.y())), 6, cv::Scalar(120), cv::FILLED);
  const Classified c = classify(rays, image);
  const RayOutcome& o = c.outcomes[static_cast<std::size_t>(row * cols + col)];
  ASSERT_TRUE(o.state == RayState::Lit || o.state == RayState::Dark) << toString(o.state);
  EXPECT_LE(o.depth, 0.6F + 0.02F) << toString(o.state) << " ray free through the spot";
  // Any ray whose segment crosses the disc ends before it.
  int crossing = 0;
  for (int i = 0; i < rows * cols; ++i)
  {
    const RayOutcome& r = c.outcomes[static_cast<std::size_t>(i)];
    if (r.state != RayState::Dark)
      continue;
    for (float z = 0.3F; z < r.depth - 0.02F; z += 0.01F)
    {
      const Eigen::Vector2d s = rig().camera.project(rays.pointAtDepth(i, z).cast<double>());
      const bool inside = (s - q).norm() < 3.0;
      crossing += inside;
      EXPECT_FALSE(inside) << "ray " << i << " is free at " << z << " m, under the bright spot";
      if (inside)
        break;
    }
  }
  EXPECT_EQ(crossing, 0);
}

TEST(RayClassifier, RefusesBadImagesAndConfigs)
{
  RayClassifier rays(rig(), DecoderConfig(), RayConfig());
  std::vector<RayOutcome> outcomes;
  const DecodeResult result;
  EXPECT_THROW(rays.classify(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), result, outcomes), std::invalid_argument);
  EXPECT_THROW(
      rays.classify(cv::Mat(rig().camera.height, rig().camera.width, CV_16UC1, cv::Scalar(0)), result, outcomes),
      std::invalid_argument);
  RayConfig far;
  far.max_range = 10.0;  // beyond the decoder's max_depth
  EXPECT_THROW(RayClassifier(rig(), DecoderConfig(), far), std::invalid_argument);
  RayConfig bad;
  bad.min_albedo = 0.0;
  try
  {
    RayClassifier r(rig(), DecoderConfig(), bad);
    ADD_FAILURE() << "min_albedo 0 accepted";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("min_albedo", 0), 0U) << e.what();
  }
}
