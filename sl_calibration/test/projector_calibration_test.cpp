// The projector as an inverse camera on synthetic correspondences: exact, noisy with wrong
// decodes, too few or coplanar views (the full round trips on rendered views are in sl_evaluation_test).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <string>

#include "sl_calibration/full_calibration.h"
#include "test_rig.h"

using namespace sl_calibration;

namespace
{
/// Planes in the camera frame: distance d along the axis, normal turned by yaw / pitch (rad).
CalibrationPlane tilted(double d, double yaw, double pitch)
{
  CalibrationPlane p;
  p.normal = Eigen::Vector3d(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
  p.offset = d * p.normal.z();
  return p;
}

/// Synthetic correspondences: every primitive the true projector throws onto the plane and the
/// camera sees, with the camera pixel perturbed by @p noise px.
std::vector<ProjectorCorrespondence> synthetic(const std::vector<CalibrationPlane>& planes, double noise, uint32_t seed)
{
  const sl_projector::Rig& rig = trueRig();
  const sl_projector::Pattern pattern(rig.pattern);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  std::vector<ProjectorCorrespondence> out;
  for (size_t v = 0; v < planes.size(); ++v)
  {
    std::vector<PrimitiveSample> samples;
    for (int r = 0; r < rig.pattern.rows; ++r)
      for (int c = 0; c < rig.pattern.cols; ++c)
      {
        const cv::Point2d q = pattern.primitiveCentroid(r, c);
        Eigen::Vector3d o, dir;
        rig.projectorRay(Eigen::Vector2d(q.x, q.y), o, dir);
        const double s = (planes[v].offset - planes[v].normal.dot(o)) / planes[v].normal.dot(dir);
        const Eigen::Vector2d px = rig.camera.project(o + s * dir);
        if (!rig.camera.inImage(px))
          continue;
        samples.push_back(PrimitiveSample{ r, c, px.x() + n(rng), px.y() + n(rng) });
      }
    const std::vector<ProjectorCorrespondence> c =
        projectorCorrespondences(pattern, rig.camera, planes[v], samples, static_cast<int>(v));
    out.insert(out.end(), c.begin(), c.end());
  }
  return out;
}

const std::vector<CalibrationPlane> kPlanes{ tilted(0.55, 0.35, 0.0), tilted(0.6, -0.35, 0.0), tilted(0.65, 0.0, 0.3),
                                             tilted(0.7, 0.0, -0.3) };

void expectClose(const sl_projector::Rig& cal, double focal_percent, double translation_mm, double rotation_deg)
{
  const RigComparison c = compareRigs(cal, trueRig());
  std::cout << c.summary();
  EXPECT_LT(std::abs(c.projector_fx_percent), focal_percent);
  EXPECT_LT(std::abs(c.projector_fy_percent), focal_percent);
  EXPECT_LT(c.translation_mm, translation_mm);
  EXPECT_LT(c.rotation_deg, rotation_deg);
}
}  // namespace

TEST(CalibrationProjector, ExactCorrespondencesGiveTheTrueProjector)
{
  const std::vector<ProjectorCorrespondence> corr = synthetic(kPlanes, 0.0, 1);
  ASSERT_GT(corr.size(), 2000u);
  const ProjectorCalibrationResult r = calibrateProjector(corr, 480, 320);
  EXPECT_LT(r.rms, 0.01);
  EXPECT_EQ(r.outliers, 0);
  sl_projector::Rig cal = trueRig();
  cal.projector = r.projector;
  cal.projector_pose = r.pose;
  expectClose(cal, 0.01, 0.01, 0.001);
  EXPECT_NEAR(r.projector.dist[0], trueRig().projector.dist[0], 1e-4);
}

TEST(CalibrationProjector, NoiseAndWrongDecodes)
{
  std::vector<ProjectorCorrespondence> corr = synthetic(kPlanes, 0.15, 2);
  // 15 % wrong decodes: the primitive taken for one 3 columns away.
  std::mt19937 rng(5);
  const sl_projector::Pattern pattern(trueRig().pattern);
  int wrong = 0;
  for (size_t i = 0; i < corr.size(); i += 7)
  {
    const int col = (corr[i].col + 3) % trueRig().pattern.cols;
    const cv::Point2d q = pattern.primitiveCentroid(corr[i].row, col);
    corr[i].projector = Eigen::Vector2d(q.x, q.y);
    ++wrong;
  }
  const ProjectorCalibrationResult r = calibrateProjector(corr, 480, 320);
  EXPECT_GE(r.outliers, wrong * 9 / 10);
  EXPECT_LT(r.rms, 0.3);
  sl_projector::Rig cal = trueRig();
  cal.projector = r.projector;
  cal.projector_pose = r.pose;
  expectClose(cal, 0.3, 0.5, 0.1);
}

TEST(CalibrationProjector, ErrorsForTooFewOrDegenerateViews)
{
  const std::vector<ProjectorCorrespondence> two = synthetic({ kPlanes[0], kPlanes[1] }, 0.0, 3);
  try
  {
    calibrateProjector(two, 480, 320);
    FAIL() << "two views";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("needs >= 3 plane poses"), std::string::npos) << e.what();
  }
  // Three "views" of the same plane: the points are coplanar.
  const std::vector<ProjectorCorrespondence> same = synthetic({ kPlanes[0], kPlanes[0], kPlanes[0] }, 0.0, 4);
  EXPECT_THROW(calibrateProjector(same, 480, 320), CalibrationError);
}
