// Full calibration on rendered views: the round trip in simulation (render the checkerboard and
// pattern views, calibrate, compare with the true rig) with the required accuracy, from the true and a
// rough rig, known camera with known-distance planes, and the errors for bad images. The projector
// fit on synthetic correspondences and the camera_info files are in sl_calibration_test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

#include "sl_calibration/full_calibration.h"
#include "sl_calibration/lens_blur.h"
#include "sl_evaluation/calibration_simulation.h"
#include "true_rig.h"

using namespace sl_decoder;
using namespace sl_calibration;
using namespace sl_evaluation;

namespace
{
/// Renders every calibration view of the simulator once: board views and plane poses.
struct SimViews
{
  Board board;
  std::vector<std::pair<std::string, cv::Mat>> boards;
  std::vector<std::tuple<std::string, cv::Mat, cv::Mat>> poses;
  cv::Mat wall700;
};

SimViews renderViews(const sl_projector::Rig& rig)
{
  SimViews v;
  const SimScenes scenes = findSimScenes();
  CalibrationSimulator sim(rig);
  uint64_t seed = 500;
  for (const std::string& path : scenes.boards)
    v.boards.emplace_back(path, sim.renderBoard(sl_sim::loadScene(path), seed++).image.clone());
  for (const std::string& path : scenes.planes)
  {
    const sl_sim::Scene scene = sl_sim::loadScene(path);
    v.board = boardOfScene(scene);
    const cv::Mat board = sim.renderBoard(scene, seed++).image.clone();
    const cv::Mat pattern =
        sim.renderPattern(withoutTextures(scene), Eigen::Isometry3d::Identity(), seed++).image.clone();
    v.poses.emplace_back(path, board, pattern);
  }
  v.wall700 = sim.renderWall(sl_sim::loadScene(scenes.wall), 0.7, PlaneCalibrationOptions(), seed++).image.clone();
  return v;
}

/// The views of the default rig (projector right of the camera), rendered once.
const SimViews& simViews()
{
  static const SimViews views = renderViews(trueRig());
  return views;
}

/// The views of test/rigs/left_rig.yaml (projector left of the camera), rendered once.
const SimViews& leftViews()
{
  static const SimViews views = renderViews(leftRig());
  return views;
}

FullCalibrationResult calibrateFrom(const sl_projector::Rig& start, const SimViews& v)
{
  FullCalibration cal(start, v.board);
  for (const auto& b : v.boards)
    cal.addCameraView(b.first, b.second);
  for (const auto& p : v.poses)
    cal.addPlaneView(std::get<0>(p) + " board", std::get<1>(p), std::get<0>(p) + " pattern", std::get<2>(p));
  return cal.calibrate();
}

void checkFloors(const FullCalibrationResult& r, const SimViews& v, const sl_projector::Rig& truth = trueRig())
{
  std::cout << r.summary();
  const RigComparison c = compareRigs(r.rig, truth);
  std::cout << c.summary();
  // The required accuracy (simulation, default noise).
  EXPECT_LT(std::abs(c.camera_fx_percent), 0.5);
  EXPECT_LT(std::abs(c.camera_fy_percent), 0.5);
  EXPECT_LT(std::abs(c.camera_cx_px), 2.0);
  EXPECT_LT(std::abs(c.camera_cy_px), 2.0);
  EXPECT_LT(std::abs(c.projector_fx_percent), 1.0);
  EXPECT_LT(std::abs(c.projector_fy_percent), 1.0);
  EXPECT_LT(c.translation_mm, 1.0);
  EXPECT_LT(std::abs(c.baseline_mm), 1.0);
  EXPECT_LT(c.rotation_deg, 0.3);
  // Reprojection errors are reported and small.
  EXPECT_LT(r.camera.rms, 0.3);
  EXPECT_LT(r.projector.rms, 0.3);
  EXPECT_EQ(r.camera.view_rms.size(), v.boards.size() + v.poses.size());
  EXPECT_EQ(r.projector.view_rms.size(), v.poses.size());
  // Depth from the calibrated file agrees with depth from the true rig at 700 mm.
  const DepthAgreement a = compareDepth(r.rig, truth, v.wall700);
  std::cout << "depth at 0.7 m vs the true rig: mean " << a.mean_mm << " mm, max " << a.max_mm << " mm over "
            << a.points << " primitives\n";
  EXPECT_GT(a.points, 600);
  EXPECT_NEAR(a.mean_z, 0.7, 0.03);
  EXPECT_LE(a.mean_mm, 1.0);
}
}  // namespace

TEST(CalibrationFull, RoundTripInSimulation)
{
  const SimViews& v = simViews();
  ASSERT_GE(v.poses.size(), 3u);
  const FullCalibrationResult r = calibrateFrom(trueRig(), v);
  EXPECT_TRUE(r.camera_calibrated);
  EXPECT_TRUE(r.refined);
  checkFloors(r, v);
  // Through the rig file and back.
  const sl_projector::Rig back = sl_projector::parseRig(sl_projector::rigToYaml(r.rig), "calibrated");
  EXPECT_NEAR(back.projector.fx, r.rig.projector.fx, 1e-6);
}

// Starting from a rig file that is off (camera focal length +1 %, principal point, projector focal
// lengths, projector 1.4 mm away): the result does not depend on the start beyond decoding.
TEST(CalibrationFull, RoundTripFromARoughRig)
{
  sl_projector::Rig start = trueRig();
  start.camera.fx *= 1.01;
  start.camera.fy *= 1.007;
  start.camera.cx += 4.0;
  start.camera.cy -= 3.0;
  start.projector.fx -= 8.0;
  start.projector.fy -= 6.0;
  start.projector.cx += 3.0;
  start.projector.cy += 3.0;
  start.projector_pose.translation += Eigen::Vector3d(0.0013, 0.0005, 0.0009);
  checkFloors(calibrateFrom(start, simViews()), simViews());
}

namespace
{
/// Prints the comparison of a calibration of the left rig with the true left rig and checks it
/// against what was measured (floors about 1.4 times the measured errors).
void checkLeft(const FullCalibrationResult& r, const std::string& what)
{
  const RigComparison c = compareRigs(r.rig, leftRig());
  const Eigen::Vector3d& t = r.rig.projector_pose.translation;
  std::printf(
      "%s: translation [%.2f, %.2f, %.2f] mm; camera fx %+.4f %% fy %+.4f %% cx %+.3f px cy %+.3f px; "
      "projector fx %+.4f %% fy %+.4f %% cx %+.3f px cy %+.3f px; translation off %.3f mm (length %+.3f "
      "mm), rotation %.4f deg; rms camera %.3f px, projector %.3f px\n",
      what.c_str(), 1000 * t.x(), 1000 * t.y(), 1000 * t.z(), c.camera_fx_percent, c.camera_fy_percent, c.camera_cx_px,
      c.camera_cy_px, c.projector_fx_percent, c.projector_fy_percent, c.projector_cx_px, c.projector_cy_px,
      c.translation_mm, c.baseline_mm, c.rotation_deg, r.camera.rms, r.projector.rms);
  // Measured from both starts: camera fx +0.040 %, fy +0.034 %, cx -0.63 px, cy +1.18 px; projector
  // fx and fy +0.074 %, cx -0.07 px, cy +0.33 px; translation 0.08 mm off (length -0.006 mm), rotation
  // 0.023 deg; reprojection rms camera 0.093 px, projector 0.036 px.
  EXPECT_LT(t.x(), -0.054) << what << ": the projector stays on the left";
  EXPECT_LT(std::abs(c.camera_fx_percent), 0.056) << what;
  EXPECT_LT(std::abs(c.camera_fy_percent), 0.048) << what;
  EXPECT_LT(std::abs(c.camera_cx_px), 0.88) << what;
  EXPECT_LT(std::abs(c.camera_cy_px), 1.65) << what;
  EXPECT_LT(std::abs(c.projector_fx_percent), 0.10) << what;
  EXPECT_LT(std::abs(c.projector_fy_percent), 0.10) << what;
  EXPECT_LT(std::abs(c.projector_cx_px), 0.10) << what;
  EXPECT_LT(std::abs(c.projector_cy_px), 0.46) << what;
  EXPECT_LT(c.translation_mm, 0.11) << what;
  EXPECT_LT(c.rotation_deg, 0.032) << what;
  EXPECT_LT(r.camera.rms, 0.13) << what;
  EXPECT_LT(r.projector.rms, 0.05) << what;
}
}  // namespace

// The projector 55 mm to the camera's LEFT (test/rigs/left_rig.yaml: the default rig mirrored):
// the required accuracy and the measured one, calibrated from the true left rig and from one
// measured with a ruler (baseline 10 mm longer, focal lengths 3 % off, the projector turned 1
// degree about each axis).
TEST(CalibrationFull, RoundTripWithTheProjectorOnTheLeft)
{
  const SimViews& v = leftViews();
  ASSERT_GE(v.poses.size(), 3u);
  const FullCalibrationResult r = calibrateFrom(leftRig(), v);
  EXPECT_TRUE(r.refined);
  checkFloors(r, v, leftRig());
  checkLeft(r, "left rig");
  // Depth at 0.7 m from the calibrated file against the true left rig: measured 0.283 mm mean.
  EXPECT_LE(compareDepth(r.rig, leftRig(), v.wall700).mean_mm, 0.39);

  sl_projector::Rig start = leftRig();
  start.projector_pose.translation.x() -= 0.010;
  start.camera.fx *= 1.03;
  start.camera.fy *= 1.03;
  start.projector.fx *= 0.97;
  start.projector.fy *= 0.97;
  const double a = M_PI / 180.0;
  start.projector_pose.rotation =
      (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix() *
      start.projector_pose.rotation;
  checkLeft(calibrateFrom(start, v), "left rig from a rough start");
}

TEST(CalibrationFull, KnownCameraAndKnownDistancePlanes)
{
  // The camera from a camera_calibration file, the planes from the plane calibration's set-up
  // (perpendicular to the robot at known distances): parallel planes at several distances are
  // enough for the projector.
  const sl_projector::Rig& rig = trueRig();
  const sl_sim::Scene wall = sl_sim::loadScene(findSimScenes().wall);
  CalibrationSimulator sim(rig);
  FullCalibration cal(rig, simViews().board);
  cal.setCamera(rig.camera);
  for (double d : { 0.5, 0.7, 0.9 })
    cal.addDistanceView("wall " + std::to_string(d), sim.renderWall(wall, d, PlaneCalibrationOptions(), 77).image, d);
  const FullCalibrationResult r = cal.calibrate();
  EXPECT_FALSE(r.camera_calibrated);
  std::cout << r.summary();
  const RigComparison c = compareRigs(r.rig, rig);
  std::cout << c.summary();
  EXPECT_EQ(c.camera_fx_percent, 0.0);
  EXPECT_LT(std::abs(c.projector_fx_percent), 1.0);
  EXPECT_LT(c.translation_mm, 1.0);
  EXPECT_LT(c.rotation_deg, 0.3);
}

TEST(CalibrationFull, ErrorsForBadInput)
{
  const SimViews& v = simViews();
  FullCalibration cal(trueRig(), v.board);
  // A checkerboard that is not there: the pattern image has none.
  try
  {
    cal.addCameraView("pattern_only.png", std::get<2>(v.poses[0]));
    FAIL() << "board found in a pattern image";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("pattern_only.png: checkerboard of 9x6 inner corners not found"),
              std::string::npos)
        << e.what();
  }
  // The wrong board size.
  FullCalibration wrong(trueRig(), parseBoardSize("7x5", 0.022));
  EXPECT_THROW(wrong.addPlaneView("b.png", std::get<1>(v.poses[0]), "p.png", std::get<2>(v.poses[0])),
               CalibrationError);
  // No pattern in the "pattern" image: the board image instead.
  try
  {
    cal.addPlaneView("b.png", std::get<1>(v.poses[0]), "dark.png", cv::Mat::zeros(480, 752, CV_8UC1));
    FAIL() << "pattern decoded in a black image";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("dark.png: only 0 pattern primitives decoded"), std::string::npos) << e.what();
  }
  // The wrong image size.
  EXPECT_THROW(cal.addCameraView("small.png", cv::Mat::zeros(240, 376, CV_8UC1)), CalibrationError);
  // Too few plane poses.
  for (size_t i = 0; i < 2; ++i)
    cal.addPlaneView("b", std::get<1>(v.poses[i]), "p", std::get<2>(v.poses[i]));
  try
  {
    cal.calibrate();
    FAIL() << "two poses";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("needs >= 3 plane poses"), std::string::npos) << e.what();
  }
  // Enough poses but too few board views for the camera (two of the three poses lack a board).
  FullCalibration few(trueRig(), v.board);
  few.addPlaneView("b", std::get<1>(v.poses[0]), "p", std::get<2>(v.poses[0]));
  for (double d : { 0.6, 0.8 })
    few.addDistanceSamples("wall", d, few.decode("p", std::get<2>(v.poses[1])));
  try
  {
    few.calibrate();
    FAIL() << "one board view";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("camera calibration needs >= 3 checkerboard views"), std::string::npos)
        << e.what();
  }
}

namespace
{
/// A white card with a 10 x 7 board of @p square m squares, its centre on the camera axis @p depth m
/// from the camera, facing it turned @p turn_deg about the vertical.
sl_sim::Scene boardScene(const sl_projector::Rig& rig, double depth, double turn_deg, double square = 0.015)
{
  const Eigen::Isometry3d camera = sl_sim::cameraPoseInWorld(rig);
  const Eigen::Vector3d axis = camera.linear().col(2);
  const Eigen::Vector3d n =
      Eigen::AngleAxisd(turn_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(-axis.x(), -axis.y(), 0.0);
  sl_sim::SceneObject card;
  card.name = "board";
  card.pose.linear().col(2) = n.normalized();
  card.pose.linear().col(0) = Eigen::Vector3d::UnitZ().cross(card.pose.linear().col(2)).normalized();
  card.pose.linear().col(1) = card.pose.linear().col(2).cross(card.pose.linear().col(0));
  card.pose.translation() = camera.translation() + depth * axis;
  card.size = Eigen::Vector3d(13 * square, 10 * square, 0.0);
  card.material.albedo = 0.85;
  card.material.texture.type = sl_sim::TextureType::Checkerboard;
  card.material.texture.cols = 10;
  card.material.texture.rows = 7;
  card.material.texture.square = square;
  card.material.texture.dark_albedo = 0.05;
  sl_sim::Scene scene;
  scene.name = "board";
  scene.objects = { card };
  return scene;
}
}  // namespace

// The camera lens's focus distance and f-number from the blur of board edges: boards at 0.40 to
// 1.10 m (two turns each), rendered with lenses unlike the rig file's defaults, their poses from the
// corners.
TEST(CalibrationLens, CameraOpticsFromBoardEdges)
{
  struct Lens
  {
    double focus, f_number, focus_tolerance, f_number_tolerance;
  };
  // Measured: focus 0.6031 m, f/2.108 (lens 1); 0.8702 m, f/1.505 (lens 2). The f-number comes out
  // 5 to 8 % high: the renderer blends blur levels, the blur is a little narrower than a thin lens's.
  for (const Lens& lens : { Lens{ 0.60, 2.0, 0.0043, 0.15 }, Lens{ 0.85, 1.4, 0.028, 0.147 } })
  {
    sl_projector::Rig rig = trueRig();
    rig.camera_optics.focus_distance = lens.focus;
    rig.camera_optics.f_number = lens.f_number;
    CalibrationSimulator sim(rig);
    const Board board = parseBoardSize("9x6", 0.015);
    std::vector<BlurSample> all, near_only;
    uint64_t seed = 900;
    for (double depth : { 0.40, 0.50, 0.60, 0.75, 0.90, 1.10 })
      for (double turn : { -25.0, 25.0 })
      {
        const cv::Mat image = sim.renderBoard(boardScene(rig, depth, turn), seed++).image;
        std::vector<cv::Point2f> corners;
        ASSERT_TRUE(findBoardCorners(image, board, corners)) << depth << " m, " << turn << " deg";
        const std::vector<EdgeBlur> edges = measureBoardEdgeBlur(image, board, corners);
        EXPECT_GT(edges.size(), 60u) << depth << " m";
        const std::vector<BlurSample> samples = blurAtDepth(edges, boardPose(rig.camera, board, corners));
        all.insert(all.end(), samples.begin(), samples.end());
        if (depth < 0.55)
          near_only.insert(near_only.end(), samples.begin(), samples.end());
      }
    const LensFit fit = fitLensOptics(all, rig.camera.fx, rig.camera_optics.pixel_pitch);
    std::printf("true focus %.3f m, f/%.2f: %s", lens.focus, lens.f_number, fit.summary("camera").c_str());
    std::printf("  focus %.4f m, f/%.3f\n", fit.lens.focus_distance, fit.lens.f_number);
    EXPECT_TRUE(fit.valid) << fit.note;
    EXPECT_NEAR(fit.lens.focus_distance, lens.focus, lens.focus_tolerance);
    EXPECT_NEAR(fit.lens.f_number, lens.f_number, lens.f_number_tolerance);
    // Boards on one side of the focus only cannot tell nearer from farther: refused, saying so.
    if (lens.focus > 0.55)
    {
      const LensFit one_side = fitLensOptics(near_only, rig.camera.fx, rig.camera_optics.pixel_pitch);
      std::cout << one_side.summary("camera (boards nearer than 0.55 m only)");
      EXPECT_FALSE(one_side.valid);
      EXPECT_NE(one_side.note.find("both sides of the focus"), std::string::npos) << one_side.note;
    }
  }
}

// The full calibration estimates the camera lens when its board views lie on both sides of the
// focus: the simulator's views (0.49 to 0.70 m, all nearer than the 0.675 m focus) do not, and the
// rig keeps the lens it had; three more board views at 0.45, 0.95 and 1.10 m give it.
TEST(CalibrationLens, FullCalibrationWritesTheCameraLens)
{
  const SimViews& v = simViews();
  sl_projector::Rig start = trueRig();
  start.camera_optics.focus_distance = 0.5;  // a wrong guess the calibration must replace or keep
  start.camera_optics.f_number = 2.8;
  FullCalibration cal(start, v.board);
  for (const auto& b : v.boards)
    cal.addCameraView(b.first, b.second);
  for (const auto& p : v.poses)
    cal.addPlaneView(std::get<0>(p) + " board", std::get<1>(p), std::get<0>(p) + " pattern", std::get<2>(p));
  const FullCalibrationResult without = cal.calibrate();
  std::cout << without.camera_lens.summary("camera (simulator's views)");
  EXPECT_FALSE(without.camera_lens.valid);
  EXPECT_NE(without.summary().find("camera lens optics not estimated: the samples"), std::string::npos);
  EXPECT_EQ(without.rig.camera_optics.focus_distance, 0.5);
  EXPECT_EQ(without.rig.camera_optics.f_number, 2.8);

  CalibrationSimulator sim(trueRig());
  uint64_t seed = 950;
  for (double depth : { 0.45, 0.95, 1.10 })
    cal.addCameraView(
        "board at " + std::to_string(depth),
        sim.renderBoard(boardScene(trueRig(), depth, depth < 0.5 ? 20.0 : -25.0, v.board.square), seed++).image);
  const FullCalibrationResult with = cal.calibrate();
  std::cout << with.camera_lens.summary("camera (with views at 0.45, 0.95, 1.10 m)");
  EXPECT_TRUE(with.camera_lens.valid) << with.camera_lens.note;
  std::printf("camera lens: focus %.4f m, f/%.3f\n", with.rig.camera_optics.focus_distance,
              with.rig.camera_optics.f_number);
  // The true lens: 0.675 m, f/1.4. Measured: 0.6762 m, f/1.431.
  EXPECT_NEAR(with.rig.camera_optics.focus_distance, 0.675, 0.0017);
  EXPECT_NEAR(with.rig.camera_optics.f_number, 1.4, 0.044);
  // Through the rig file.
  const sl_projector::Rig back = sl_projector::parseRig(sl_projector::rigToYaml(with.rig), "calibrated");
  EXPECT_NEAR(back.camera_optics.focus_distance, with.rig.camera_optics.focus_distance, 1e-6);
  // The extra views leave the geometry within the required accuracy.
  const RigComparison c = compareRigs(with.rig, trueRig());
  EXPECT_LT(std::abs(c.camera_fx_percent), 0.5);
  EXPECT_LT(std::abs(c.projector_fx_percent), 1.0);
  EXPECT_LT(c.translation_mm, 1.0);
  EXPECT_LT(c.rotation_deg, 0.3);
}
