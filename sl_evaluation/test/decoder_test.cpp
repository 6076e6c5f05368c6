// Decoding of images rendered by the project's simulator, checked against its ground truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sl_evaluation/evaluation.h"
#include "true_rig.h"

using namespace sl_decoder;
using namespace sl_evaluation;

namespace
{
EvalStats run(const sl_projector::Rig& rig, const std::vector<std::string>& scene, int frames = 2,
              const DecoderConfig& config = DecoderConfig())
{
  const SceneReport r = evaluateScene(rig, findScene(scene), config, frames);
  const EvalStats& s = r.stats;
  std::cout << std::fixed << std::setprecision(3) << r.scene << ": visible " << s.visible / s.frames << ", valid "
            << s.validPercent() << "%, wrong " << s.wrong << ", unverifiable " << s.unverifiable << ", mean "
            << s.meanErrorMm() << " mm, max " << s.maxErrorMm() << " mm, near points "
            << static_cast<double>(s.near_points) / s.frames << " per frame\n"
            << std::defaultfloat;
  return s;
}

/// What a scene must reach. Renders are seeded (1000, 1001, ... as in sl_eval), so the measured values
/// repeat exactly from run to run; the floors leave a small margin for another CPU's floating point.
/// Where doc/results.md's table (sl_eval, 3 frames) prints a value, valid % and mean error are
/// one unit of its last digit from it (0.1 %: 1-3 primitives in 3 frames; 0.01 mm); the max error,
/// a single point, about 5 %; near points 5 % below.
struct Floors
{
  double valid_percent;   ///< at least
  double mean_mm;         ///< at most
  double max_mm;          ///< at most: one bad point (a wrong depth at a silhouette) shows here first
  double near_per_frame;  ///< points on nearer surfaces per frame, at least (the objects are decoded)
  double near_at_most;    ///< and at most (0 on a lone plane: no phantom surface in front of it)
};

const double kAny = 1e9;  // no upper bound on near points (a nearer object may show more of itself)

/// Checks every statistic the scoring prints; no point may be wrong or unverifiable.
void expectFloors(const EvalStats& s, const Floors& f, const std::string& what)
{
  const double near = static_cast<double>(s.near_points) / s.frames;
  EXPECT_GT(s.visible, 0) << what;
  EXPECT_GE(s.validPercent(), f.valid_percent) << what;
  EXPECT_EQ(s.wrong, 0) << what;
  EXPECT_EQ(s.unverifiable, 0) << what;
  EXPECT_LE(s.meanErrorMm(), f.mean_mm) << what;
  EXPECT_LE(s.maxErrorMm(), f.max_mm) << what;
  EXPECT_GE(near, f.near_per_frame) << what;
  EXPECT_LE(near, f.near_at_most) << what;
}
}  // namespace

// Default simulator settings, full triangulation. The requirement (97 % valid, 1 mm mean on the
// 700 mm plane) is far below what is reached: the doc/results.md's figures are asserted instead.
TEST(Decoder, PlaneAt700mm)
{
  const EvalStats s = run(trueRig(), { "plane_700" }, 3);
  EXPECT_GT(s.visible, 3 * 600);
  // doc/results.md: 100.0 %, 0.11 mm mean, max 5.9. Measured: 100.000 %, 0.109 mm, max 5.85 mm, no near point.
  expectFloors(s, { 99.9, 0.12, 6.1, 0.0, 0.0 }, "plane_700");
}

TEST(Decoder, ThreePlanes)
{
  const EvalStats s = run(trueRig(), { "three_planes" }, 3);
  // doc/results.md: 97.8 %, 0.16 mm mean, max 6.16, 529 near points per frame (the two nearer planes).
  // Measured: 97.821 %, 0.163 mm, max 6.16 mm, 529.0 near points per frame.
  expectFloors(s, { 97.7, 0.17, 6.5, 500.0, kAny }, "three_planes");
}

// The doc/results.md's claim for the sweep, as printed there (rounded): valid 95.7..99.6 %, mean 0.08..0.36 mm
// at every step. Measured (3 frames each): valid 95.666 % (850 mm) .. 99.592 % (600 mm), mean
// 0.080 mm (600 mm) .. 0.364 mm (950 mm), max 0.54 mm (500 mm) .. 9.88 mm (900 mm).
TEST(Decoder, PlanesFrom450To950mm)
{
  for (int mm = 450; mm <= 950; mm += 50)
  {
    const EvalStats s = run(trueRig(), { "plane_" + std::to_string(mm) }, 3);
    // Near points: none in front of a plane, but at 950 mm 29 per frame on the floor at its foot.
    // Floors a little under the doc/results.md's 95.7..99.6 % and 0.08..0.36 mm: the worst steps (850 mm,
    // 950 mm) sit on them within a third of a primitive and 0.001 mm, too close for another CPU.
    const Floors floors{ 95.0, 0.40, 10.4, mm < 950 ? 0.0 : 27.0, mm < 950 ? 0.0 : 31.0 };
    expectFloors(s, floors, "plane_" + std::to_string(mm));
  }
}

/// Decodes @p frames renders of a table-leg scene and returns the fewest points on the leg in a frame
/// (points within 3 mm of its surface, the leg's axis at (@p axis_x, 0) in the world); none may be
/// wrong.
int fewestPointsOnLeg(const char* scene_name, double axis_x, double radius, int frames)
{
  const sl_projector::Rig& rig = trueRig();
  const sl_sim::Scene scene = sl_sim::loadScene(findScene({ scene_name }));
  sl_sim::Renderer renderer(rig);
  Decoder decoder(rig);
  const cv::Mat pattern = decoder.pattern().render();
  const Eigen::Isometry3d camera_in_world = sl_sim::cameraPoseInWorld(rig);
  sl_sim::RenderOutput truth;
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

// The doc/results.md's claims: 32+ points on the 20 mm leg and 24+ on the 12 mm leg in every frame. Measured
// (5 frames): 32 and 24 in the worst frame.
TEST(Decoder, TwentyMillimetreLegHasPointsInEveryFrame)
{
  const int fewest = fewestPointsOnLeg("table_leg_20mm", 0.655, 0.010, 5);
  std::cout << "table_leg_20mm: at least " << fewest << " points on the leg per frame\n";
  EXPECT_GE(fewest, 30);  // measured 32 (doc/results.md: 32+), two points of margin for another CPU
}

TEST(Decoder, TwelveMillimetreLegHasPointsInEveryFrame)
{
  const int fewest = fewestPointsOnLeg("table_leg_12mm", 0.651, 0.006, 5);
  std::cout << "table_leg_12mm: at least " << fewest << " points on the leg per frame\n";
  EXPECT_GE(fewest, 22);  // measured 24 (doc/results.md: 24+), two points of margin for another CPU
}

// Objects in front of a plane: the object must be decoded (near points), not only left undecoded.
TEST(Decoder, ObjectsBeforePlanes)
{
  // doc/results.md: 96.5 %, 0.23 mm mean, max 9.9 (the silhouette), 357 near points per frame.
  // Measured: 96.456 %, 0.233 mm, max 9.93 mm, 357.0 near points per frame.
  expectFloors(run(trueRig(), { "cylinder_plane_650" }, 3), { 96.4, 0.24, 10.4, 340.0, kAny }, "cylinder");
  // doc/results.md: 94.5 % (the saturated highlight loses primitives; 89.7 % without split_merged),
  // 0.97 mm mean, max 26, 633.0 near. Measured (sl_eval): 94.5 %, 0.97 mm, max 25.98 mm, 633.0 near.
  expectFloors(run(trueRig(), { "shiny_bin_586" }, 3), { 94.4, 0.98, 27.3, 600.0, kAny }, "shiny bin");
  // doc/results.md: 99.7 %, 0.21 mm mean, max 6.12, 27.3 near. Measured: 99.680 %, 0.209 mm, 6.12 mm, 27.3.
  expectFloors(run(trueRig(), { "table_leg_12mm" }, 3), { 99.6, 0.22, 6.4, 26.0, kAny }, "12 mm leg");
  // doc/results.md: 99.9 %, 0.18 mm mean, max 9.98, 34.7 near. Measured: 99.918 %, 0.184 mm, 9.98 mm, 34.7.
  expectFloors(run(trueRig(), { "table_leg_20mm" }, 3), { 99.8, 0.19, 10.5, 33.0, kAny }, "20 mm leg");
}

// Nothing may assume the default rig: another resolution, focal length and distortion, with the
// projector on the other side of the camera.
TEST(Decoder, WorksWithAnotherRig)
{
  sl_projector::Rig rig = trueRig();
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
  // Measured: 98.452 %, 0.258 mm, max 3.39 mm, no near point; floors one primitive per frame (0.12 %)
  // and about 5 % from them.
  expectFloors(run(rig, { "plane_700" }, 2), { 98.3, 0.27, 3.6, 0.0, 0.0 }, "plane_700, other rig");
  // Measured: 98.067 %, 0.310 mm, max 6.61 mm, 527 near points (the nearer planes).
  expectFloors(run(rig, { "three_planes" }, 1), { 97.9, 0.33, 7.0, 500.0, kAny }, "three_planes, other rig");
}

namespace
{
/// A plane at @p distance m from the camera, 2 frames from seed @p seed.
EvalStats runPlane(const sl_projector::Rig& rig, double distance, const sl_sim::SimSettings& settings, uint64_t seed,
                   const std::string& what)
{
  DecoderConfig config;
  config.split_merged = true;  // the near-range detection (the default; stated, as the floors need it)
  const SceneReport r = evaluateScene(rig, planeScene(rig, distance), what, config, 2, settings, seed);
  const EvalStats& s = r.stats;
  std::cout << std::fixed << std::setprecision(3) << what << " " << distance << " m (seed " << seed << "): visible "
            << s.visible / s.frames << ", valid " << s.validPercent() << "%, wrong " << s.wrong << ", mean "
            << s.meanErrorMm() << " mm, max " << s.maxErrorMm() << " mm\n"
            << std::defaultfloat;
  return s;
}
}  // namespace

// Near range, where the robot stops: defocus and overexposure merge the primitives into rows; the
// detector splits them at raised thresholds or at the pattern's pitch (split_merged). Two seeds per
// distance.
TEST(Decoder, NearRangeDefaultRig)
{
  const sl_sim::SimSettings settings;
  for (uint64_t seed : { 1000u, 2000u })
  {
    // Measured (seeds 1000, 2000; 1000..1002 and 1000..1004 in sl_eval): 67.9 to 68.2 %, 0.63 to 0.64 mm mean, max
    // 5.8 mm. The rows are saturated bands there, read from their outline.
    expectFloors(runPlane(trueRig(), 0.35, settings, seed, "near plane"), { 67.0, 0.7, 7.0, 0.0, 0.0 }, "0.35 m");
    // Measured: 96.7 to 96.9 %, 0.83 mm mean, max 3.0 mm.
    expectFloors(runPlane(trueRig(), 0.40, settings, seed, "near plane"), { 95.5, 0.9, 4.0, 0.0, 0.0 }, "0.40 m");
    // Measured: 98.2 %, 0.22 mm mean.
    expectFloors(runPlane(trueRig(), 0.45, settings, seed, "near plane"), { 97.5, 0.3, 1.5, 0.0, 0.0 }, "0.45 m");
  }
}

// Twice the projector's defocus blur (f/0.9 instead of f/1.8) at 0.45 m.
TEST(Decoder, NearRangeHeavyProjectorBlur)
{
  sl_sim::SimSettings settings;
  settings.projector_f_number = 0.9;
  for (uint64_t seed : { 1000u, 2000u })
    // Measured: 95.7 to 95.9 %, 0.83 mm mean, max 3.1 mm.
    expectFloors(runPlane(trueRig(), 0.45, settings, seed, "f/0.9 plane"), { 94.5, 0.9, 4.0, 0.0, 0.0 }, "f/0.9");
}

// The second rig of test/rigs: 640 x 480, fx 1100, the projector 70 mm to the camera's left, both
// lenses mildly distorted and focused at 0.70 m.
TEST(Decoder, SecondRigNearAndFar)
{
  const sl_projector::Rig rig = sl_projector::loadRig(std::string(SL_EVALUATION_TEST_DIR) + "/rigs/second_rig.yaml");
  sl_sim::SimSettings settings;
  settings.camera_focus_distance = settings.projector_focus_distance = 0.70;
  // Measured: 97.7 % at 0.45 m (0.37 mm mean), 97.6 to 98.3 % from 0.55 to 0.95 m (0.28 to 0.72 mm).
  expectFloors(runPlane(rig, 0.45, settings, 1000, "second rig"), { 96.5, 0.5, 2.0, 0.0, 0.0 }, "0.45 m");
  for (double d : { 0.55, 0.65, 0.75, 0.85, 0.95 })
    expectFloors(runPlane(rig, d, settings, 1000, "second rig"), { 96.5, 0.85, 9.0, 0.0, 0.0 }, std::to_string(d));
}

// Beyond the scene files' 950 mm: nothing may get worse out to 1.2 m, where the near-range work
// must not cost anything (`sl_eval --plane 1.0 --plane 1.1 --plane 1.2 --frames 2`).
TEST(Decoder, DefaultRigPlanesTo1200mm)
{
  const sl_sim::SimSettings settings;
  // Measured: 98.3, 98.2, 98.2 %; mean 0.59, 0.76, 1.13 mm (the floor in front of the plane gives
  // 56 to 132 near points per frame).
  const double mean_ceiling[] = { 0.75, 0.95, 1.4 };
  int k = 0;
  for (double d : { 1.0, 1.1, 1.2 })
  {
    const EvalStats s = runPlane(trueRig(), d, settings, 1000, "far plane");
    EXPECT_GE(s.validPercent(), 97.5) << d << " m";
    EXPECT_LE(s.meanErrorMm(), mean_ceiling[k++]) << d << " m";
    EXPECT_EQ(s.wrong, 0) << d << " m";
    EXPECT_EQ(s.unverifiable, 0) << d << " m";
  }
}

// sl_eval's near and far rows (`sl_eval --rig test/rigs/left_rig.yaml --near-far --defocus-scale S`,
// 2 frames) on the default rig with the projector mirrored to the camera's LEFT: the decoder's
// figures there, the far planes whatever the blur, and no wrong point anywhere.
TEST(Decoder, LeftRigNearAndFarRows)
{
  const sl_projector::Rig rig = sl_projector::loadRig(std::string(SL_EVALUATION_TEST_DIR) + "/rigs/left_rig.yaml");
  ASSERT_LT(rig.projector_pose.translation.x(), -0.05);
  // At defocus x1, measured valid % and mean error (mm) at 0.35, 0.40, 0.45, 0.55, 0.70, 0.90, 1.20 m:
  // 66.1 / 0.66, 97.0 / 0.87, 98.0 / 0.22, 98.1 / 0.11, 98.4 / 0.09, 99.9 / 0.30, 99.7 / 1.12.
  const std::vector<double> valid_floor{ 64.0, 95.5, 97.0, 97.0, 97.5, 98.5, 98.5 };
  const std::vector<double> mean_ceiling{ 0.85, 1.1, 0.3, 0.15, 0.13, 0.4, 1.5 };
  const std::vector<double>& distances = nearFarDistances();
  ASSERT_EQ(distances.size(), valid_floor.size());
  for (double scale : { 0.5, 1.0, 1.5 })
  {
    sl_sim::SimSettings settings;
    settings.defocus_scale = scale;
    for (size_t i = 0; i < distances.size(); ++i)
    {
      char what_text[64];
      std::snprintf(what_text, sizeof(what_text), "left rig, defocus x%.1f", scale);
      const std::string what = what_text;
      const EvalStats s = runPlane(rig, distances[i], settings, 1000, what);
      std::cout << "  decode " << s.decodeMs() << " ms (median of " << s.decode_seconds.size() << ")\n";
      EXPECT_EQ(s.wrong, 0) << what << ", " << distances[i] << " m";
      EXPECT_EQ(s.unverifiable, 0) << what << ", " << distances[i] << " m";
      EXPECT_EQ(s.decode_seconds.size(), 2u);
      if (scale == 1.0)
      {
        EXPECT_GE(s.validPercent(), valid_floor[i]) << what << ", " << distances[i] << " m";
        EXPECT_LE(s.meanErrorMm(), mean_ceiling[i]) << what << ", " << distances[i] << " m";
      }
      // From 0.55 m on the blur does not matter: measured 98.0 to 99.9 % at x0.5 and x1.5.
      if (distances[i] > 0.5)
      {
        EXPECT_GE(s.validPercent(), 97.0) << what << ", " << distances[i] << " m";
      }
    }
  }
}

// Per-primitive tables built from the true rig reproduce triangulation: a rational model fitted
// exactly to three depths on each primitive's curve.
TEST(Decoder, RationalTablesMatchTriangulation)
{
  sl_projector::Rig rig = trueRig();
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

// The detector's SSE2 and AVX2 thresholds give the portable path's blobs bit for bit on rendered
// frames too (far, near and blurred, cluttered), so a decode does not depend on the CPU it runs on.
TEST(Decoder, VectorPathsGiveIdenticalBlobsOnRenderedFrames)
{
  const sl_projector::Rig& rig = trueRig();
  const Decoder decoder(rig);
  sl_sim::Renderer renderer(rig);
  sl_sim::RenderOutput frame;
  std::vector<sl_sim::Scene> scenes = { sl_sim::loadScene(findScene({ "plane_950" })),
                                        sl_sim::loadScene(findScene({ "room" })), planeScene(rig, 0.36, 0.3) };
  int compared = 0;
  for (size_t s = 0; s < scenes.size(); ++s)
  {
    renderer.render(scenes[s], decoder.pattern().render(), sl_sim::cameraPoseInWorld(rig), 11 + s, frame);
    BlobDetector detector(decoder.config());
    std::vector<Blob> reference, blobs;
    detector.useSimd(BlobDetector::Simd::Portable);
    detector.detect(frame.image, reference);
    ASSERT_GT(reference.size(), 100u) << "scene " << s;
    for (BlobDetector::Simd path : { BlobDetector::Simd::Sse2, BlobDetector::Simd::Avx2 })
    {
      if (detector.useSimd(path) != path)
        continue;
      detector.detect(frame.image, blobs);
      ASSERT_EQ(blobs.size(), reference.size()) << "scene " << s;
      for (size_t i = 0; i < blobs.size(); ++i)
      {
        const Blob &a = blobs[i], &b = reference[i];
        ASSERT_TRUE(a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1 && a.area == b.area &&
                    a.level == b.level && std::memcmp(&a.u, &b.u, sizeof a.u) == 0 &&
                    std::memcmp(&a.v, &b.v, sizeof a.v) == 0 &&
                    std::memcmp(&a.contrast, &b.contrast, sizeof a.contrast) == 0)
            << "scene " << s << " blob " << i;
      }
      ++compared;
    }
  }
  EXPECT_GE(compared, 3) << "SSE2 runs on every x86-64 CPU";
}
