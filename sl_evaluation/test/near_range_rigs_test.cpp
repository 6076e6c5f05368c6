// Near range on rigs the decoder was not tuned on: rigs drawn at random (fixed seeds) around the
// default one, planes rendered by the project's simulator with its defocus scaled (lenses unlike
// the rig file's), scored against the renderer's ground truth. doc/results.md ("Near range on
// generated rigs") has the table this test prints.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "sl_evaluation/evaluation.h"
#include "true_rig.h"

using namespace sl_decoder;
using namespace sl_evaluation;

namespace
{
/// A rig of the family, and how it was drawn (for the messages).
struct FamilyRig
{
  sl_projector::Rig rig;
  std::string what;
};

/// The projector pixel the camera axis at @p depth falls on.
Eigen::Vector2d axisPixel(const sl_projector::Rig& rig, double depth)
{
  return rig.projector.project(rig.projector_pose.inverse() * Eigen::Vector3d(0.0, 0.0, depth));
}

/**
 * @brief A rig drawn from the default one: projector left or right, baseline 40 to 90 mm, both
 * focal lengths within +-25 %, other distortion, the projector rolled by up to +-2 deg, both lenses
 * focused at 0.5 to 0.9 m. The projector stays aimed as in the default rig: the camera axis at
 * 0.675 m meets the same projector pixel (mirrored for a projector on the left).
 */
FamilyRig drawRig(uint32_t seed, bool left)
{
  std::mt19937 rng(seed);
  auto uniform = [&rng](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  const sl_projector::Rig& base = trueRig();
  const Eigen::Vector2d aim = axisPixel(base, 0.675);
  sl_projector::Rig rig = base;
  const double baseline = uniform(0.040, 0.090);
  const double cam_scale = uniform(0.75, 1.25), proj_scale = uniform(0.75, 1.25);
  const double roll = uniform(-2.0, 2.0) * M_PI / 180.0;
  rig.camera.fx *= cam_scale;
  rig.camera.fy *= cam_scale;
  rig.camera.dist = { uniform(-0.15, 0.05), uniform(-0.05, 0.15), uniform(-1e-3, 1e-3), uniform(-1e-3, 1e-3), 0.0 };
  rig.projector.fx *= proj_scale;
  rig.projector.fy *= proj_scale;
  rig.projector.dist = { uniform(-0.05, 0.05), uniform(-0.02, 0.02), 0.0, 0.0, 0.0 };
  rig.projector_pose.translation *= baseline / base.projector_pose.translation.norm();
  rig.projector_pose.rotation = rig.projector_pose.rotation * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ());
  if (left)
  {
    Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
    mirror(0, 0) = -1.0;
    rig.projector_pose.rotation = mirror * rig.projector_pose.rotation * mirror;
    rig.projector_pose.translation.x() = -rig.projector_pose.translation.x();
  }
  const Eigen::Vector2d target(left ? (rig.projector.width - 1) - aim.x() : aim.x(), aim.y());
  const Eigen::Vector2d now = axisPixel(rig, 0.675);
  rig.projector.cx += target.x() - now.x();
  rig.projector.cy += target.y() - now.y();
  const double focus = uniform(0.5, 0.9);
  rig.camera_optics.focus_distance = rig.projector_optics.focus_distance = focus;
  rig.validate();
  char text[160];
  std::snprintf(text, sizeof(text), "rig %u %-5s (baseline %2.0f mm, f x%.2f / x%.2f, roll %+.1f deg, focus %.2f m)",
                seed, left ? "left" : "right", 1000.0 * baseline, cam_scale, proj_scale, roll * 180.0 / M_PI, focus);
  return { rig, text };
}

/// One plane of one rig: its scores and how much of the primitives' shape the optics leave.
struct Case
{
  double distance;
  double blur;  ///< the renderer's defocus_scale
  double rho;   ///< blur (Gaussian sigma) / the primitive's width in the image, from the optics
  EvalStats stats;
};

/// A plane at @p distance m, 2 frames from @p seed, the renderer's defocus scaled by @p blur.
Case runPlane(const FamilyRig& r, const Decoder& optics, double distance, double blur, uint64_t seed)
{
  sl_sim::SimSettings settings;
  settings.defocus_scale = blur;
  Case c{ distance, blur, optics.patternBlur(distance, blur) / optics.primitiveWidth(), EvalStats() };
  c.stats = evaluateScene(r.rig, planeScene(r.rig, distance), "plane", DecoderConfig(), 2, settings, seed).stats;
  const EvalStats& s = c.stats;
  std::printf("%s %.2f m, blur x%.1f, rho %.2f: valid %5.1f %% of %d, wrong %d, mean %.2f mm, max %.2f mm\n",
              r.what.c_str(), distance, blur, c.rho, s.validPercent(), s.visible / s.frames, s.wrong, s.meanErrorMm(),
              s.maxErrorMm());
  return c;
}

/// The floor of valid % at a near distance.
double nearFloor(double distance)
{
  return distance < 0.375 ? 80.0 : distance < 0.425 ? 90.0 : 95.0;
}
}  // namespace

// Ten rigs (seeds 1 to 5, projector right and left), planes at 0.35, 0.40 and 0.45 m with the
// renderer's defocus x0.5, x1 and x1.5, and at 0.6, 0.9 and 1.2 m with it x1. rho (the optics'
// blur sigma over the primitive's width, Decoder::patternBlur) tells where the lenses still leave
// the primitives' shapes.
TEST(NearRangeRigs, FamilyOfGeneratedRigs)
{
  std::vector<Case> near, far;
  for (uint32_t seed = 1; seed <= 5; ++seed)
    for (bool left : { false, true })
    {
      const FamilyRig r = drawRig(seed, left);
      const Decoder optics(r.rig);
      for (double d : { 0.35, 0.40, 0.45 })
        for (double blur : { 0.5, 1.0, 1.5 })
          near.push_back(runPlane(r, optics, d, blur, 1000 + seed));
      for (double d : { 0.60, 0.90, 1.20 })
        far.push_back(runPlane(r, optics, d, 1.0, 1000 + seed));
    }
  // Never a wrong correspondence, on any rig, at any blur.
  for (const Case& c : near)
  {
    EXPECT_EQ(c.stats.wrong, 0) << c.distance << " m, blur x" << c.blur;
  }
  for (const Case& c : far)
  {
    EXPECT_EQ(c.stats.wrong, 0) << c.distance << " m";
  }
  // Where the optics leave the shapes (rho <= 0.2), the floors hold on every rig. Measured:
  // 36 of the 90 near cases, valid 97.0 to 99.8 %, mean error at most 0.42 mm.
  // Beyond, saturated rows blurred by a sigma of a third of a primitive or more lose most of their
  // outline: measured, the floors (80 / 90 / 95 %, 1.5 mm) hold in 15 of 30 cases at 0.35 m, 19 at
  // 0.40 m, 24 at 0.45 m (doc/results.md lists each).
  for (double d : { 0.35, 0.40, 0.45 })
  {
    int meeting = 0;
    for (const Case& c : near)
    {
      if (std::abs(c.distance - d) > 1e-9)
        continue;
      const bool meets = c.stats.validPercent() >= nearFloor(d) && c.stats.meanErrorMm() <= 1.5;
      meeting += meets;
      if (c.rho <= 0.2)
      {
        EXPECT_TRUE(meets) << d << " m, blur x" << c.blur << ", rho " << c.rho << ": valid " << c.stats.validPercent()
                           << " %, mean " << c.stats.meanErrorMm() << " mm";
      }
    }
    std::printf("%.2f m: the floors hold on %d of 30 rig and blur cases\n", d, meeting);
    EXPECT_GE(meeting, d < 0.375 ? 13 : d < 0.425 ? 17 : 22) << d << " m";
  }
  // Farther: the defocus of a lens focused at 0.5 m ends decoding beyond about 0.9 m (rho above
  // 0.3: 4 to 6 % at 1.2 m, as before the near-range work); elsewhere measured valid 94.8 to
  // 100 %, mean error at most 3.15 mm.
  for (const Case& c : far)
  {
    if (c.rho > 0.3)
      continue;
    EXPECT_GE(c.stats.validPercent(), 94.0) << c.distance << " m, rho " << c.rho;
    EXPECT_LE(c.stats.meanErrorMm(), 3.5) << c.distance << " m, rho " << c.rho;
  }
}
