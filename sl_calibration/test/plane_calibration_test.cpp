// Plane calibration without rendered images: the fits on exact and noisy data, the plane geometry,
// the errors for bad input and an inconsistent primitive refused (the round trips on rendered views
// are in sl_evaluation_test).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "sl_calibration/plane_calibration.h"
#include "test_rig.h"

using namespace sl_calibration;

namespace
{
// A rational depth curve of the kind a primitive follows: z = (a + b u) / (1 + c u).
double curve(double u)
{
  return (0.9 - 0.0012 * u) / (1.0 - 0.0021 * u) + 0.0;
}
}  // namespace

TEST(CalibrationFit, RationalIsExactWithThreePoints)
{
  const std::vector<double> u{ 150.0, 210.0, 260.0 };
  std::vector<double> z;
  for (double x : u)
    z.push_back(curve(x));
  const sl_projector::DepthModel m = fitRational(u, z);
  ASSERT_TRUE(m.valid);
  EXPECT_LT(m.rms, 1e-12);
  for (double x = 140.0; x <= 270.0; x += 5.0)
    EXPECT_NEAR(m.depth(x), curve(x), 1e-9) << x;
}

TEST(CalibrationFit, RationalLeastSquaresWithNoise)
{
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.0002);
  std::vector<double> u, z;
  for (double x = 140.0; x <= 270.0; x += 10.0)
  {
    u.push_back(x);
    z.push_back(curve(x) + noise(rng));
  }
  const sl_projector::DepthModel m = fitRational(u, z);
  ASSERT_TRUE(m.valid);
  EXPECT_NEAR(m.rms, 0.0002, 0.0001);
  for (double x = 140.0; x <= 270.0; x += 5.0)
    EXPECT_NEAR(m.depth(x), curve(x), 0.0003) << x;
}

TEST(CalibrationFit, RationalWithThePoleNearColumnZero)
{
  // A primitive whose infinite-depth column is near u = 0 (a, b, c become large but stay exact).
  auto z = [](double u) { return 60.0 / (u - 0.01); };
  const std::vector<double> u{ 70.0, 90.0, 120.0, 150.0 };
  std::vector<double> d;
  for (double x : u)
    d.push_back(z(x));
  const sl_projector::DepthModel m = fitRational(u, d);
  ASSERT_TRUE(m.valid);
  for (double x = 70.0; x <= 150.0; x += 10.0)
    EXPECT_NEAR(m.depth(x), z(x), 1e-7) << x;
}

TEST(CalibrationFit, LinearAndDegenerateInput)
{
  const sl_projector::DepthModel two = fitLinear({ 100.0, 200.0 }, { 0.8, 0.6 });
  ASSERT_TRUE(two.valid);
  EXPECT_NEAR(two.depth(150.0), 0.7, 1e-12);
  EXPECT_FALSE(fitLinear({ 100.0 }, { 0.8 }).valid);
  EXPECT_FALSE(fitLinear({ 100.0, 100.0 }, { 0.8, 0.6 }).valid);
  EXPECT_FALSE(fitRational({ 100.0, 200.0 }, { 0.8, 0.6 }).valid);
  EXPECT_FALSE(fitRational({ 100.0, 100.0, 100.0 }, { 0.8, 0.7, 0.6 }).valid);
  // The linear model cannot follow the curvature: over 140..270 px it misses by millimetres.
  std::vector<double> u, z;
  for (double x = 140.0; x <= 270.0; x += 10.0)
  {
    u.push_back(x);
    z.push_back(curve(x));
  }
  EXPECT_GT(fitLinear(u, z).rms, 0.001);
}

TEST(CalibrationPlaneGeometry, DistanceDefinitions)
{
  const sl_projector::Rig& rig = trueRig();
  PlaneCalibrationOptions o;
  const CalibrationPlane cam = planeAtDistance(rig, 0.7, o);
  EXPECT_NEAR(cam.offset, 0.7, 1e-12);
  EXPECT_NEAR(cam.normal.norm(), 1.0, 1e-12);
  // The camera is yawed by mount.rpy.z: the robot's x axis is that far off its optical axis.
  EXPECT_NEAR(std::acos(cam.normal.z()), std::abs(rig.mount.rpy.z()), 1e-9);
  o.reference = DistanceReference::Edge;
  const CalibrationPlane edge = planeAtDistance(rig, 0.7, o);
  EXPECT_NEAR(edge.offset, 0.7 - rig.mount.xyz.x(), 1e-12);  // the camera is 30 mm behind the edge
  o.reference = DistanceReference::Camera;
  o.normal = PlaneNormal::Camera;
  const CalibrationPlane axis = planeAtDistance(rig, 0.6, o);
  EXPECT_NEAR(depthOnPlane(rig.camera, axis, 10.0, 400.0), 0.6, 1e-12);
  // On the robot-perpendicular plane, depth at the image centre is the offset over cos(yaw).
  EXPECT_NEAR(depthOnPlane(rig.camera, cam, rig.camera.cx, rig.camera.cy), 0.7 / cam.normal.z(), 1e-9);
  EXPECT_THROW(planeAtDistance(rig, -0.5, PlaneCalibrationOptions()), std::invalid_argument);
}

TEST(CalibrationPlane, ErrorsForBadInput)
{
  const sl_projector::Rig& rig = trueRig();
  PlaneCalibration cal(rig);
  try
  {
    cal.fit();
    FAIL() << "no images";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("no images"), std::string::npos) << e.what();
  }
  const std::vector<PrimitiveSample> samples{ { 5, 20, 300.0, 200.0 }, { 5, 21, 314.0, 200.0 } };
  cal.addSamples(0.7, samples, "a.png");
  cal.addSamples(0.7, samples, "b.png");
  try
  {
    cal.fit();
    FAIL() << "one distance only";
  }
  catch (const CalibrationError& e)
  {
    const std::string m = e.what();
    EXPECT_NE(m.find(">= 3 different distances, got 1"), std::string::npos) << m;
    EXPECT_NE(m.find("0.700 m (2 images, 2 primitives)"), std::string::npos) << m;
  }
  // Three distances, but every primitive at only one of them.
  cal.addSamples(0.6, { { 6, 20, 320.0, 220.0 } }, "c.png");
  cal.addSamples(0.5, { { 7, 20, 340.0, 240.0 } }, "d.png");
  try
  {
    cal.fit();
    FAIL() << "no primitive at 3 distances";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("4 of the 4 primitives seen were seen at fewer than 3 distances"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(cal.addSamples(700.0, samples, "mm.png"), CalibrationError);  // mm given
  EXPECT_THROW(cal.addSamples(std::nan(""), samples, "nan.png"), CalibrationError);
  PlaneCalibrationOptions bad;
  bad.min_distances = 2;
  EXPECT_THROW(PlaneCalibration(rig, bad), std::invalid_argument);
}

// A primitive whose rational fit leaves more than max_rational_rms (3 mm) is refused: it gets no
// table entry and is reported as rejected; one inconsistent distance of five is left out instead.
TEST(CalibrationPlane, InconsistentPrimitiveIsRefused)
{
  PlaneCalibrationOptions options;
  options.normal = PlaneNormal::Camera;  // the target depth is the distance itself
  PlaneCalibration cal(trueRig(), options);
  const double distances[5] = { 0.5, 0.6, 0.7, 0.8, 0.9 };
  // Image columns of a primitive on planes at depth z: u = 300 + 80 / z (disparity ~ 1 / z).
  const double zigzag[5] = { 6.0, -6.0, 6.0, -6.0, 6.0 };  // 6 px is 20 to 60 mm of depth
  const double one_bad[5] = { 0.0, 0.0, 9.0, 0.0, 0.0 };   // a wrong decode at 0.7 m
  for (int k = 0; k < 5; ++k)
  {
    const double u = 300.0 + 80.0 / distances[k];
    std::vector<PrimitiveSample> samples(3);
    samples[0] = PrimitiveSample{ 0, 0, u, 200.0 };
    samples[1] = PrimitiveSample{ 0, 1, u + zigzag[k], 200.0 };
    samples[2] = PrimitiveSample{ 0, 2, u + one_bad[k], 200.0 };
    EXPECT_EQ(cal.addSamples(distances[k], samples, "synthetic"), 3);
  }
  const PlaneCalibrationResult res = cal.fit();
  EXPECT_EQ(res.calibrated, 2);
  EXPECT_EQ(res.rejected, 1);
  ASSERT_EQ(res.tables.rational.size(), 16u * 64u);
  EXPECT_TRUE(res.tables.rational[0].valid);
  EXPECT_FALSE(res.tables.rational[1].valid) << "the zigzag primitive must not be calibrated";
  EXPECT_TRUE(res.tables.rational[2].valid) << "one bad distance of five is left out";
  EXPECT_LT(res.tables.rational[2].rms, 1e-6);
  EXPECT_NE(res.residualsCsv().find("rejected"), std::string::npos);
}
