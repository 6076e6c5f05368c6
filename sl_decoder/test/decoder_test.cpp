// The decoder on images and rigs that need no rendering: bad images, rigs it must refuse, the optics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_decoder/decoder.h"
#include "sl_decoder/epipolar_index.h"
#include "sl_decoder/ray_approach.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"

using namespace sl_decoder;

namespace
{
const sl_projector::Rig& defaultRig()
{
  static const sl_projector::Rig rig = sl_projector::loadRig(SL_PROJECTOR_CONFIG_DIR "/default_rig.yaml");
  return rig;
}
}  // namespace

TEST(Decoder, BadImagesAreHandled)
{
  Decoder decoder(defaultRig());
  DecodeResult result;
  for (int level : { 0, 255, 128 })
  {
    decoder.decode(cv::Mat(480, 752, CV_8UC1, cv::Scalar(level)), result);
    EXPECT_EQ(result.valid, 0) << level;
    EXPECT_EQ(result.decoded, 0) << level;
  }
  EXPECT_THROW(decoder.decode(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), result), std::invalid_argument);
  EXPECT_THROW(decoder.decode(cv::Mat(480, 752, CV_16UC1, cv::Scalar(0)), result), std::invalid_argument);
  EXPECT_THROW(decoder.decode(cv::Mat(), result), std::invalid_argument);
}

// A rig with a 262144 x 262144 camera made sl_decode segfault: the table sizes overflowed int and
// the buffers came out too small. Both entry points refuse it before allocating anything.
TEST(Decoder, HugeCamerasAreRefusedNotOverflowed)
{
  for (const auto& size : { std::make_pair(262144, 262144), std::make_pair(400000, 300000) })
  {
    sl_projector::Rig rig = defaultRig();
    rig.camera.width = size.first;
    rig.camera.height = size.second;
    EXPECT_THROW(Decoder{ rig }, std::invalid_argument) << size.first;
    // The index checks its own sizes too (it does not rely on the rig having been validated).
    try
    {
      EpipolarIndex index(rig, DecoderConfig());
      ADD_FAILURE() << "a " << size.first << " x " << size.second << " camera was accepted";
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_EQ(std::string(e.what()).rfind("camera image: ", 0), 0u) << e.what();
    }
  }
}

// The optics' blur of the pattern: the thin lens with the rig file's lenses, as the simulator
// renders it (doc/simulator.md: sigma 2.11 px at 450 mm, 0.66 at 675 mm on the default rig).
TEST(Decoder, PatternBlurFollowsTheRigsLenses)
{
  const Decoder decoder(defaultRig());
  EXPECT_NEAR(decoder.patternBlur(0.45), 2.11, 0.01);
  EXPECT_NEAR(decoder.patternBlur(0.675), std::sqrt(0.09 + 0.09 * std::pow(1492.0 / 753.0, 2)), 1e-9);
  EXPECT_GT(decoder.patternBlur(0.35), decoder.patternBlur(0.40));
  // Lenses that blur 1.5 times more.
  EXPECT_GT(decoder.patternBlur(0.45, 1.5), 1.4 * decoder.patternBlur(0.45));
  // Another focus moves the sharpest depth.
  sl_projector::Rig near_focus = defaultRig();
  near_focus.camera_optics.focus_distance = near_focus.projector_optics.focus_distance = 0.45;
  EXPECT_LT(Decoder(near_focus).patternBlur(0.45), 0.7);
  // A primitive's width in the image: 5 of 7 projector px of a cell, fx 1492 / 753 camera px each.
  EXPECT_NEAR(decoder.primitiveWidth(), 5.0 * 1492.0 / 753.0, 0.5);
}

TEST(Decoder, DepthTablesAreRequiredForTableModes)
{
  DecoderConfig c;
  c.depth_mode = DepthMode::Rational;
  EXPECT_THROW(Decoder(defaultRig(), c), std::invalid_argument);
  c.depth_mode = DepthMode::Linear;
  EXPECT_THROW(Decoder(defaultRig(), c), std::invalid_argument);
  c = DecoderConfig();
  c.min_depth = -1.0;
  EXPECT_THROW(Decoder(defaultRig(), c), std::invalid_argument);
}

// The per-shape look-up is the plain look-up filtered by primitive value, order kept: the decoder
// checks only the primitives of a blob's shape, in index order.
TEST(EpipolarIndex, ShapeListsAreTheCandidatesOfThatValue)
{
  const sl_projector::Rig& rig = defaultRig();
  const EpipolarIndex index(rig, DecoderConfig());
  const sl_projector::Pattern pattern(rig.pattern);
  const std::vector<int>& values = pattern.array().values();
  size_t listed = 0;
  for (float v = -3.f; v < rig.camera.height + 3.f; v += 2.5f)
    for (float u = -3.f; u < rig.camera.width + 3.f; u += 2.5f)
    {
      const int32_t *all, *all_end;
      index.candidates(u, v, all, all_end);
      size_t total = 0;
      for (int shape = 0; shape <= 5; ++shape)
      {
        std::vector<int32_t> expected;
        for (const int32_t* p = all; p != all_end; ++p)
          if (values[static_cast<size_t>(*p)] == shape)
            expected.push_back(*p);
        const int32_t *it, *end;
        index.candidates(u, v, shape, it, end);
        ASSERT_EQ(std::vector<int32_t>(it, end), expected) << u << " " << v << " shape " << shape;
        EXPECT_TRUE(std::is_sorted(it, end));  // index order, as the curves were traced
        total += expected.size();
      }
      EXPECT_EQ(total, static_cast<size_t>(all_end - all));
      listed += total;
      const int32_t *it, *end;
      index.candidates(u, v, -1, it, end);
      EXPECT_EQ(it, end);
    }
  EXPECT_GT(listed, 0u);
}

// The decoder computes its candidates' geometry two at a time (SSE2): bit for bit what one at a
// time gives, on random rays, near-parallel ones included.
TEST(RayApproach, TwoAtATimeIsBitIdenticalToOneAtATime)
{
  cv::RNG rng(5);
  auto unit = [&](double spread)
  {
    const Eigen::Vector3d v(rng.uniform(-spread, spread), rng.uniform(-spread, spread), 1.0);
    return Eigen::Vector3d(v.normalized());
  };
  auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (a != a && b != b); };
  for (int i = 0; i < 20000; ++i)
  {
    CameraRayTerms cam;
    cam.o = Eigen::Vector3d(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.05, 0.05));
    cam.fx = rng.uniform(200.0, 1500.0);
    cam.d1 = unit(0.8);
    cam.d1o = cam.d1.dot(cam.o);
    const Eigen::Vector3d a = i % 7 == 0 ? cam.d1 : unit(0.8), b = unit(0.8);  // some parallel to the camera ray
    RayApproach ra, rb;
    rayApproach2(cam, a, a.dot(cam.o), b, b.dot(cam.o), ra, rb);
    const RayApproach ea = rayApproach(cam, a, a.dot(cam.o)), eb = rayApproach(cam, b, b.dot(cam.o));
    for (const auto& pair : { std::make_pair(ra, ea), std::make_pair(rb, eb) })
    {
      ASSERT_TRUE(same(pair.first.denom, pair.second.denom)) << i;
      ASSERT_TRUE(same(pair.first.z, pair.second.z)) << i;
      ASSERT_TRUE(same(pair.first.u, pair.second.u)) << i;
      ASSERT_TRUE(same(pair.first.epipolar_px, pair.second.epipolar_px)) << i;
    }
  }
}
