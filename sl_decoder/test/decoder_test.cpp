// Decoding of images rendered by the project's simulator, checked against its ground truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sl_decoder/evaluation.h"

using namespace sl_decoder;

namespace
{
const sl_projector::Rig& defaultRig()
{
  static const sl_projector::Rig rig = sl_projector::loadRig(defaultRigFile());
  return rig;
}

EvalStats run(const sl_projector::Rig& rig, const std::vector<std::string>& scene, int frames = 2,
              const DecoderConfig& config = DecoderConfig())
{
  const SceneReport r = evaluateScene(rig, findScene(scene), config, frames);
  const EvalStats& s = r.stats;
  std::cout << r.scene << ": visible " << s.visible / s.frames << ", valid " << s.validPercent() << "%, wrong "
            << s.wrong << ", unverifiable " << s.unverifiable << ", mean " << s.meanErrorMm() << " mm, max "
            << s.maxErrorMm() << " mm, near points " << s.near_points << "\n";
  return s;
}
}  // namespace

// The floors at default simulator settings with full triangulation.
TEST(Decoder, PlaneAt700mm)
{
  const EvalStats s = run(defaultRig(), { "plane_700" }, 3);
  EXPECT_GT(s.visible, 3 * 600);
  EXPECT_GE(s.validPercent(), 97.0);
  EXPECT_EQ(s.wrong, 0);
  EXPECT_LE(s.meanErrorMm(), 1.0);
}

TEST(Decoder, ThreePlanes)
{
  const EvalStats s = run(defaultRig(), { "three_planes" }, 3);
  EXPECT_GE(s.validPercent(), 85.0);
  EXPECT_EQ(s.wrong, 0);
  EXPECT_LE(s.meanErrorMm(), 2.0);
}

TEST(Decoder, PlanesFrom450To950mm)
{
  for (int mm = 450; mm <= 950; mm += 50)
  {
    const EvalStats s = run(defaultRig(), { "plane_" + std::to_string(mm) }, 1);
    EXPECT_GT(s.valid, 100) << mm;
    EXPECT_EQ(s.wrong, 0) << mm;
    EXPECT_LE(s.meanErrorMm(), 3.0) << mm;
  }
}

/// Decodes @p frames renders of a table-leg scene and returns the fewest points on the leg in a frame
/// (points within 3 mm of its surface, the leg's axis at (@p axis_x, 0) in the world); none may be
/// wrong.
int fewestPointsOnLeg(const char* scene_name, double axis_x, double radius, int frames)
{
  const sl_projector::Rig& rig = defaultRig();
  const sl_camera::Scene scene = sl_camera::loadScene(findScene({ scene_name }));
  sl_camera::Renderer renderer(rig);
  Decoder decoder(rig);
  const cv::Mat pattern = decoder.pattern().render();
  const Eigen::Isometry3d camera_in_world = sl_camera::cameraPoseInWorld(rig);
  sl_camera::RenderOutput truth;
  DecodeResult result;
  int fewest = 1 << 30;
  for (int seed = 1; seed <= frames; ++seed)
  {
    renderer.render(scene, pattern, camera_in_world, static_cast<uint64_t>(seed), truth);
    decoder.decode(truth.image, result);
    const EvalStats s = evaluateFrame(decoder.pattern(), truth, result);
    EXPECT_EQ(s.wrong, 0) << scene_name << " seed " << seed;
    int on_leg = 0;
    for (const Blob& b : result.blobs)
    {
      if (!b.valid)
        continue;
      const Eigen::Vector3d w = camera_in_world * Eigen::Vector3d(b.x, b.y, b.z);
      on_leg += std::abs(std::hypot(w.x() - axis_x, w.y()) - radius) < 0.003 && w.z() > 0.0 && w.z() < 0.72;
    }
    fewest = std::min(fewest, on_leg);
  }
  return fewest;
}

TEST(Decoder, TwentyMillimetreLegHasPointsInEveryFrame)
{
  const int fewest = fewestPointsOnLeg("table_leg_20mm", 0.655, 0.010, 5);
  std::cout << "table_leg_20mm: at least " << fewest << " points on the leg per frame\n";
  EXPECT_GE(fewest, 3);
}

TEST(Decoder, TwelveMillimetreLegHasPointsInEveryFrame)
{
  // The issue sets no floor for the 12 mm leg; measured: 24 or more points per frame. A floor of 10
  // keeps it from quietly disappearing.
  const int fewest = fewestPointsOnLeg("table_leg_12mm", 0.651, 0.006, 5);
  std::cout << "table_leg_12mm: at least " << fewest << " points on the leg per frame\n";
  EXPECT_GE(fewest, 10);
}

TEST(Decoder, NoWrongCorrespondencesInAnyScene)
{
  for (const char* name : { "cylinder_plane_650", "shiny_bin_586", "table_leg_12mm", "table_leg_20mm" })
  {
    const EvalStats s = run(defaultRig(), { name }, 2);
    EXPECT_EQ(s.wrong, 0) << name;
  }
}

// Nothing may assume the default rig: another resolution, focal length and distortion, with the
// projector on the other side of the camera.
TEST(Decoder, WorksWithAnotherRig)
{
  sl_projector::Rig rig = defaultRig();
  rig.camera.width = 640;
  rig.camera.height = 400;
  rig.camera.fx = rig.camera.fy = 1250.0;
  rig.camera.cx = 322.0;
  rig.camera.cy = 197.0;
  rig.camera.dist = { 0.06, -0.1, -0.0004, 0.0002, 0.0 };
  // Mirror the geometry left-right: the projector moves to the camera's left.
  Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
  mirror(0, 0) = -1.0;
  rig.projector_pose.rotation = mirror * rig.projector_pose.rotation * mirror;
  rig.projector_pose.translation.x() = -rig.projector_pose.translation.x();
  rig.projector.cx = (rig.projector.width - 1) - rig.projector.cx;
  rig.validate();
  Decoder decoder(rig);
  EXPECT_TRUE(decoder.index().epipolarAlongRows());
  EXPECT_LT(decoder.index().projectorOrigin().x(), 0.0) << "the projector is on the camera's left now";
  const EvalStats s = run(rig, { "plane_700" }, 2);
  EXPECT_GE(s.validPercent(), 90.0);
  EXPECT_EQ(s.wrong, 0);
  EXPECT_LE(s.meanErrorMm(), 1.5);
  const EvalStats t = run(rig, { "three_planes" }, 1);
  EXPECT_EQ(t.wrong, 0);
}

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

// Per-primitive tables built from the true rig reproduce triangulation: a rational model fitted
// exactly to three depths on each primitive's curve.
TEST(Decoder, RationalTablesMatchTriangulation)
{
  sl_projector::Rig rig = defaultRig();
  const sl_projector::Pattern pattern(rig.pattern);
  const size_t cells = static_cast<size_t>(rig.pattern.rows * rig.pattern.cols);
  rig.tables.rational.resize(cells);
  const sl_projector::RigidTransform to_proj = rig.projector_pose.inverse();
  (void)to_proj;
  for (int r = 0; r < rig.pattern.rows; ++r)
    for (int c = 0; c < rig.pattern.cols; ++c)
    {
      const cv::Point2d p = pattern.primitiveCentroid(r, c);
      Eigen::Vector3d o, d;
      rig.projectorRay(Eigen::Vector2d(p.x, p.y), o, d);
      // depth z = (a + b u) / (1 + c u)  =>  a + b u - c u z = z: three points fix a, b, c.
      Eigen::Matrix3d A;
      Eigen::Vector3d rhs;
      int k = 0;
      for (double z : { 0.5, 0.7, 0.9 })
      {
        const Eigen::Vector3d point = o + (z - o.z()) / d.z() * d;
        const double u = rig.camera.project(point).x();
        A.row(k) << 1.0, u, -u * z;
        rhs(k) = z;
        ++k;
      }
      const Eigen::Vector3d abc = A.colPivHouseholderQr().solve(rhs);
      rig.tables.rational[static_cast<size_t>(r * rig.pattern.cols + c)] =
          sl_projector::DepthModel{ true, abc(0), abc(1), abc(2), 0.0 };
    }
  DecoderConfig config;
  config.depth_mode = DepthMode::Rational;
  const EvalStats rational = run(rig, { "plane_700" }, 1, config);
  const EvalStats tri = run(rig, { "plane_700" }, 1);
  EXPECT_EQ(rational.valid, tri.valid);
  // Off the decoded point's own row the rational model ignores the small vertical parallax; it
  // must still agree with triangulation to a fraction of a millimetre.
  EXPECT_NEAR(rational.meanErrorMm(), tri.meanErrorMm(), 0.5);
}
