// Plane calibration: the fits on exact and noisy data, the plane geometry, the round trip in
// simulation (render the wall at known distances, calibrate, evaluate on distances not used) with
// the floors, and the errors for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <Eigen/Geometry>

#include "sl_decoder/calibration/plane_calibration.h"
#include "sl_evaluation/calibration_simulation.h"

using namespace sl_decoder;
using namespace sl_decoder::calibration;
using namespace sl_evaluation;

namespace
{
const sl_projector::Rig& trueRig()
{
  static const sl_projector::Rig rig = sl_projector::loadRig(defaultRigFile());
  return rig;
}

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

TEST(CalibrationPlaneGeometry, SimulatedWallAgreesWithTheDefinition)
{
  // The simulator's wall at D and the calibration's plane at D are the same plane: the ground-truth
  // depth of the rendered image matches depthOnPlane() everywhere on the wall.
  const sl_projector::Rig& rig = trueRig();
  const sl_sim::Scene wall = sl_sim::loadScene(findSimScenes().wall);
  CalibrationSimulator sim(rig);
  PlaneCalibrationOptions o;
  const sl_sim::RenderOutput& out = sim.renderWall(wall, 0.65, o, 1);
  const CalibrationPlane plane = planeAtDistance(rig, 0.65, o);
  int checked = 0;
  for (int v = 20; v < 300; v += 40)
    for (int u = 20; u < 740; u += 60)
    {
      const float z = out.depth.at<float>(v, u);
      ASSERT_TRUE(std::isfinite(z));
      EXPECT_NEAR(z, depthOnPlane(rig.camera, plane, u, v), 2e-5) << u << "," << v;
      ++checked;
    }
  EXPECT_GT(checked, 50);
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

// The round trip in simulation: calibrate on the wall at 0.5, 0.6, 0.7, 0.8, 0.9 m, evaluate both
// models on 0.55, 0.65, 0.75, 0.85 m. Floor: rational mean |depth error| <= 1 mm; the linear model's
// error is reported beside it and shows the curvature.
TEST(CalibrationPlane, RoundTripInSimulation)
{
  const sl_projector::Rig& rig = trueRig();
  const sl_sim::Scene wall = sl_sim::loadScene(findSimScenes().wall);
  CalibrationSimulator sim(rig);
  PlaneCalibrationOptions options;
  PlaneCalibration cal(rig, options);
  Decoder decoder(rig, calibrationDecoderConfig());
  DecodeResult result;
  uint64_t seed = 100;
  for (double d : { 0.5, 0.6, 0.7, 0.8, 0.9 })
  {
    decoder.decode(sim.renderWall(wall, d, options, seed++).image, result);
    EXPECT_GT(cal.addImage(d, result, "wall"), 600) << d;
  }
  const PlaneCalibrationResult res = cal.fit();
  std::cout << res.summary();
  EXPECT_GT(res.calibrated, 750);
  EXPECT_EQ(res.rejected, 0);
  EXPECT_LT(res.rational_rms, 0.0005);
  EXPECT_GT(res.linear_rms, 0.005);  // the curvature over 0.5..0.9 m
  EXPECT_EQ(res.tables.rational.size(), 16u * 64u);

  // Through the rig file and back.
  const sl_projector::Rig calibrated = sl_projector::parseRig(sl_projector::rigToYaml(withTables(rig, res)), "cal");
  ASSERT_EQ(calibrated.tables.rational.size(), 16u * 64u);
  ASSERT_EQ(calibrated.tables.distances.size(), 5u);

  EvalStats rational, linear;
  std::printf("distance_m  rational_mean_mm  linear_mean_mm\n");
  for (double d : { 0.55, 0.65, 0.75, 0.85 })
  {
    const sl_sim::RenderOutput& truth = sim.renderWall(wall, d, options, seed++);
    const EvalStats r = evaluateRendered(calibrated, DepthMode::Rational, truth);
    const EvalStats l = evaluateRendered(calibrated, DepthMode::Linear, truth);
    std::printf("%10.3f  %16.3f  %14.3f\n", d, r.meanErrorMm(), l.meanErrorMm());
    EXPECT_GT(r.with_depth, 500) << d;
    EXPECT_LE(r.meanErrorMm(), 1.0) << d;
    EXPECT_EQ(r.wrong, 0) << d;
    rational.add(r);
    linear.add(l);
  }
  std::printf("all         %16.3f  %14.3f\n", rational.meanErrorMm(), linear.meanErrorMm());
  EXPECT_LE(rational.meanErrorMm(), 1.0);
  EXPECT_GT(linear.meanErrorMm(), 3.0 * rational.meanErrorMm());
}

// With exactly three planes the rational model is exact on them (zero residual) and still close on
// the planes between.
TEST(CalibrationPlane, ThreePlanesAreExact)
{
  const sl_projector::Rig& rig = trueRig();
  const sl_sim::Scene wall = sl_sim::loadScene(findSimScenes().wall);
  CalibrationSimulator sim(rig);
  PlaneCalibrationOptions options;
  PlaneCalibration cal(rig, options);
  Decoder decoder(rig, calibrationDecoderConfig());
  DecodeResult result;
  for (double d : { 0.55, 0.7, 0.85 })
  {
    decoder.decode(sim.renderWall(wall, d, options, 300).image, result);
    cal.addImage(d, result);
  }
  const PlaneCalibrationResult res = cal.fit();
  EXPECT_GT(res.calibrated, 600);
  EXPECT_LT(res.rational_rms, 1e-9);
  const EvalStats r =
      evaluateRendered(withTables(rig, res), DepthMode::Rational, sim.renderWall(wall, 0.625, options, 301));
  std::cout << "three planes, evaluated at 0.625 m: mean " << r.meanErrorMm() << " mm\n";
  EXPECT_LE(r.meanErrorMm(), 1.0);
}

namespace
{
/// The true rig as a ruler would measure it: baseline @p sign * 10 mm longer, camera focal lengths
/// 3 % longer and the projector's 3 % shorter, and the projector turned 1 degree about each axis.
sl_projector::Rig roughRig(double sign)
{
  sl_projector::Rig rig = trueRig();
  rig.projector_pose.translation.x() += sign * 0.010;
  rig.camera.fx *= 1.0 + sign * 0.03;
  rig.camera.fy *= 1.0 + sign * 0.03;
  rig.projector.fx *= 1.0 - sign * 0.03;
  rig.projector.fy *= 1.0 - sign * 0.03;
  const double a = sign * M_PI / 180.0;
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(-a, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  rig.projector_pose.rotation = turn * rig.projector_pose.rotation;
  rig.validate();
  return rig;
}
}  // namespace

// Calibration from a roughly measured rig: the views are identified by the code, so no identity is
// wrong (the geometric decoder with such a rig mislabels about 100 primitives per view, every one
// shifted by a whole row), and the rational tables fitted from them are as good as from the true
// rig on planes not used for fitting.
TEST(CalibrationPlane, RoughRigIsIdentifiedByTheCode)
{
  const sl_sim::Scene wall = sl_sim::loadScene(findSimScenes().wall);
  CalibrationSimulator sim(trueRig());
  PlaneCalibrationOptions options;
  for (double sign : { 1.0, -1.0 })
  {
    const sl_projector::Rig rough = roughRig(sign);
    PlaneCalibration cal(rough, options);
    Decoder decoder(rough, calibrationDecoderConfig());
    DecodeResult result;
    uint64_t seed = 400;
    for (double d : { 0.5, 0.6, 0.7, 0.8, 0.9 })
    {
      const sl_sim::RenderOutput& truth = sim.renderWall(wall, d, options, seed++);
      decoder.decode(truth.image, result);
      const EvalStats s = evaluateFrame(decoder.pattern(), truth, result);
      // Measured: 726 (0.9 m) to 901 (0.6 m) decoded of 727 to 898 visible, none wrong.
      EXPECT_EQ(s.wrong, 0) << "rough rig " << sign << ", " << d << " m";
      EXPECT_GT(cal.addImage(d, result, "wall"), 700) << d;
    }
    const PlaneCalibrationResult res = cal.fit();
    std::printf("rough rig %+.0f: %d primitives calibrated\n", sign, res.calibrated);
    EXPECT_GT(res.calibrated, 700) << sign;
    EXPECT_EQ(res.rejected, 0) << sign;
    DecoderConfig config = calibrationDecoderConfig();
    config.depth_mode = DepthMode::Rational;
    Decoder calibrated(withTables(rough, res), config);
    EvalStats all;
    for (double d : { 0.55, 0.65, 0.75, 0.85 })
    {
      const sl_sim::RenderOutput& truth = sim.renderWall(wall, d, options, seed++);
      calibrated.decode(truth.image, result);
      const EvalStats s = evaluateFrame(calibrated.pattern(), truth, result);
      std::printf("rough rig %+.0f: %.2f m: %d points, %d wrong, mean %.3f mm\n", sign, d, s.valid, s.wrong,
                  s.meanErrorMm());
      EXPECT_EQ(s.wrong, 0) << d;
      EXPECT_GT(s.with_depth, 680) << d;  // measured 707 (0.85 m) to 789
      all.add(s);
    }
    EXPECT_LE(all.meanErrorMm(), 0.3) << sign;  // measured 0.17 and 0.18 mm
  }
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
