// Full calibration: the projector as an inverse camera on synthetic correspondences (exact, noisy,
// with wrong decodes), the round trip in simulation (render the checkerboard and pattern views,
// calibrate, compare with the true rig) with the floors, and the errors for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <tuple>
#include <random>
#include <string>

#include <unistd.h>

#include <opencv2/calib3d.hpp>

#include "sl_decoder/calibration/full_calibration.h"
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

TEST(CalibrationCamera, CameraInfoRoundTripAndErrors)
{
  const sl_projector::PinholeModel& cam = trueRig().camera;
  const std::string prefix = ::testing::TempDir() + "/sl_calibration_" + std::to_string(getpid()) + "_";
  const std::string path = prefix + "camera_info.yaml";
  saveCameraInfo(cam, path, "sl_camera");
  const sl_projector::PinholeModel back = loadCameraInfo(path);
  EXPECT_EQ(back.width, cam.width);
  EXPECT_DOUBLE_EQ(back.fx, cam.fx);
  EXPECT_DOUBLE_EQ(back.cy, cam.cy);
  for (size_t i = 0; i < 5; ++i)
    EXPECT_DOUBLE_EQ(back.dist[i], cam.dist[i]);
  // ROS camera_calibration's layout, 5 coefficients, block style.
  const std::string ros = prefix + "ost.yaml";
  {
    std::ofstream o(ros);
    o << "image_width: 752\nimage_height: 480\ncamera_name: narrow_stereo\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
         "  data: [1490.5, 0, 371.2, 0, 1491.5, 244.1, 0, 0, 1]\ndistortion_model: plumb_bob\n"
         "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [-0.081, 0.13, 0.0004, -0.0002, 0]\n"
         "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"
         "projection_matrix:\n  rows: 3\n  cols: 4\n  data: [1490.5, 0, 371.2, 0, 0, 1491.5, 244.1, 0, 0, 0, 1, 0]\n";
  }
  const sl_projector::PinholeModel r = loadCameraInfo(ros);
  EXPECT_DOUBLE_EQ(r.fy, 1491.5);
  EXPECT_DOUBLE_EQ(r.dist[1], 0.13);
  const std::string bad = prefix + "bad.yaml";
  {
    std::ofstream o(bad);
    o << "image_width: 752\nimage_height: 480\ncamera_matrix:\n  data: [1, 0, 2]\n";
  }
  try
  {
    loadCameraInfo(bad);
    FAIL();
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("camera_matrix.data: has 3 numbers, expected 9"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(loadCameraInfo(prefix + "does_not_exist.yaml"), CalibrationError);
  for (const std::string& f : { path, ros, bad })
    std::remove(f.c_str());
}

TEST(CalibrationCamera, BoardSizeParsing)
{
  const Board b = parseBoardSize("9x6", 0.022);
  EXPECT_EQ(b.cols, 9);
  EXPECT_EQ(b.rows, 6);
  EXPECT_EQ(b.objectPoints().size(), 54u);
  EXPECT_THROW(parseBoardSize("9by6", 0.022), std::invalid_argument);
  EXPECT_THROW(parseBoardSize("6x6", 0.022), std::invalid_argument);  // symmetric: orientation ambiguous
  EXPECT_THROW(parseBoardSize("9x6", 22.0), std::invalid_argument);   // mm given
}

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

const SimViews& simViews()
{
  static const SimViews views = []
  {
    SimViews v;
    const SimScenes scenes = findSimScenes();
    CalibrationSimulator sim(trueRig());
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
  }();
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

void checkFloors(const FullCalibrationResult& r, const SimViews& v)
{
  std::cout << r.summary();
  const RigComparison c = compareRigs(r.rig, trueRig());
  std::cout << c.summary();
  // The floors (simulation, default noise).
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
  const DepthAgreement a = compareDepth(r.rig, trueRig(), v.wall700);
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
