#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "sl_rig/rig.h"

using namespace sl_projector;

namespace
{
const std::string kDefaultRig = std::string(SL_PROJECTOR_CONFIG_DIR) + "/default_rig.yaml";
// Pieces of the default rig file the tests replace.
const std::string kCameraK = "  K: [1492.0, 0.0, 372.0, 0.0, 1492.0, 243.0, 0.0, 0.0, 1.0]";
const std::string kPatternBlock =
    "pattern:\n  rows: 16\n  cols: 64\n  primitive_width: 5\n  primitive_height: 9\n"
    "  gap_x: 2\n  gap_y: 6\n  offset_x: 0\n  offset_y: 0\n  flip_x: false\n  flip_y: false\n";

std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Replaces the first occurrence of @p from in @p text.
std::string replaced(std::string text, const std::string& from, const std::string& to)
{
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos)
    text.replace(at, from.size(), to);
  return text;
}

// The error message of parsing @p text, or "" if it parses.
std::string parseError(const std::string& text)
{
  try
  {
    parseRig(text, "test.yaml");
  }
  catch (const RigFileError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Rig, DefaultRigLoads)
{
  const Rig rig = loadRig(kDefaultRig);
  EXPECT_EQ(rig.camera.width, 752);
  EXPECT_EQ(rig.camera.height, 480);
  EXPECT_DOUBLE_EQ(rig.camera.fx, 1492.0);
  EXPECT_EQ(rig.projector.width, 480);
  EXPECT_DOUBLE_EQ(rig.projector.fy, 781.0);
  EXPECT_NEAR(rig.projector_pose.translation.norm(), 0.0568, 0.001);
  EXPECT_NEAR(Eigen::AngleAxisd(rig.projector_pose.rotation).angle() * 180.0 / M_PI, 12.7, 0.05);
  EXPECT_EQ(rig.pattern.rows, 16);
  EXPECT_EQ(rig.pattern.projector_width, 480);
  EXPECT_EQ(rig.mount.parent_frame, "platform_edge");
  EXPECT_TRUE(rig.tables.linear.empty());
}

TEST(Rig, ProjectAndRayRoundTripWithDistortion)
{
  const Rig rig = loadRig(kDefaultRig);
  for (const PinholeModel* m : { &rig.camera, &rig.projector })
  {
    for (double u = 0; u < m->width; u += m->width / 7.0)
      for (double v = 0; v < m->height; v += m->height / 5.0)
      {
        const Eigen::Vector3d r = m->ray(Eigen::Vector2d(u, v));
        const Eigen::Vector2d back = m->project(0.7 * r);
        EXPECT_NEAR(back.x(), u, 1e-7);
        EXPECT_NEAR(back.y(), v, 1e-7);
      }
  }
  EXPECT_TRUE(std::isnan(rig.camera.project(Eigen::Vector3d(0.0, 0.0, -1.0)).x()));
}

TEST(Rig, TriangulationRecoversPoints)
{
  const Rig rig = loadRig(kDefaultRig);
  const RigidTransform cam_to_proj = rig.projector_pose.inverse();
  int checked = 0;
  for (double z : { 0.45, 0.675, 0.95 })
    for (int i = -3; i <= 3; ++i)
      for (int j = -2; j <= 2; ++j)
      {
        const Eigen::Vector3d p(0.05 * i, 0.04 * j, z);
        const Eigen::Vector2d cam = rig.camera.project(p);
        const Eigen::Vector2d proj = rig.projector.project(cam_to_proj * p);
        Eigen::Vector3d q;
        double gap = 1.0;
        ASSERT_TRUE(rig.triangulate(cam, proj, q, &gap));
        EXPECT_LT((q - p).norm(), 1e-7);
        EXPECT_LT(gap, 1e-7);
        ++checked;
      }
  EXPECT_EQ(checked, 3 * 7 * 5);
}

// The mount and optics put the working window (331 x 173 mm from the floor up, centred on the
// robot) inside the camera image and inside the projected pattern at 675 mm from the camera.
TEST(Rig, DefaultRigCoversTheWorkingWindowAt675mm)
{
  const Rig rig = loadRig(kDefaultRig);
  const RigidTransform optical = rig.mount.cameraOpticalInParent();
  const RigidTransform edge_to_cam = optical.inverse();
  const RigidTransform cam_to_proj = rig.projector_pose.inverse();
  const Pattern pattern(rig.pattern);
  const cv::Point2d first = pattern.primitiveCentroid(0, 0);
  const cv::Point2d last = pattern.primitiveCentroid(rig.pattern.rows - 1, rig.pattern.cols - 1);
  const double x_edge = 0.675 + rig.mount.xyz.x();  // 675 mm in front of the camera
  for (double y : { -0.1655, 0.1655 })
    for (double z : { 0.0, 0.173 })
    {
      const Eigen::Vector3d p_cam = edge_to_cam * Eigen::Vector3d(x_edge, y, z);
      const Eigen::Vector2d px = rig.camera.project(p_cam);
      EXPECT_TRUE(rig.camera.inImage(px)) << "window corner y=" << y << " z=" << z << " at pixel " << px.transpose();
      const Eigen::Vector2d pp = rig.projector.project(cam_to_proj * p_cam);
      EXPECT_GT(pp.x(), first.x) << y << " " << z;
      EXPECT_LT(pp.x(), last.x) << y << " " << z;
      EXPECT_GT(pp.y(), first.y) << y << " " << z;
      EXPECT_LT(pp.y(), last.y) << y << " " << z;
    }
  // Optical axis: z_opt along the robot's x (slightly yawed), camera above the floor.
  EXPECT_GT(optical.rotation.col(2).x(), 0.99);
  EXPECT_NEAR(optical.translation.z(), 0.0865, 1e-12);
}

TEST(Rig, RoundTripsThroughYamlWithTables)
{
  Rig rig = loadRig(kDefaultRig);
  const size_t cells = static_cast<size_t>(rig.pattern.rows * rig.pattern.cols);
  rig.tables.distances = { 0.5, 0.6, 0.7 };
  rig.tables.rational.resize(cells);
  rig.tables.linear.resize(cells);
  for (size_t i = 0; i < cells; i += 3)
  {
    rig.tables.rational[i] = DepthModel{ true, 1.0 + i, -0.001, 1e-4, 2e-4 };
    rig.tables.linear[i] = DepthModel{ true, 2.0, -0.002 * i, 0.0, 1e-3 };
  }
  const Rig back = parseRig(rigToYaml(rig), "round trip");
  EXPECT_EQ(back.camera.cx, rig.camera.cx);
  EXPECT_EQ(back.camera.dist, rig.camera.dist);
  EXPECT_TRUE(back.projector_pose.rotation.isApprox(rig.projector_pose.rotation, 1e-12));
  EXPECT_EQ(back.mount.rpy, rig.mount.rpy);
  ASSERT_EQ(back.tables.rational.size(), cells);
  ASSERT_EQ(back.tables.linear.size(), cells);
  EXPECT_EQ(back.tables.distances, rig.tables.distances);
  for (size_t i = 0; i < cells; ++i)
  {
    ASSERT_EQ(back.tables.rational[i].valid, i % 3 == 0) << i;
    if (i % 3 == 0)
    {
      EXPECT_DOUBLE_EQ(back.tables.rational[i].a, 1.0 + i);
      EXPECT_DOUBLE_EQ(back.tables.rational[i].c, 1e-4);
      EXPECT_DOUBLE_EQ(back.tables.linear[i].b, -0.002 * i);
    }
  }
  EXPECT_NEAR(back.tables.rational[0].depth(100.0), (1.0 - 0.1) / (1.0 + 0.01), 1e-12);
}

// Found by fuzz/rig_parser_fuzz.cpp (corpus: baseline_at_limit_round_trip.yaml): written with 12
// digits, a baseline of 0.1000000000001 mm came back as the 0.1 mm limit and the written file was
// refused. Every number now reads back exactly, and the file stays readable.
TEST(Rig, RoundTripIsExact)
{
  Rig rig = loadRig(kDefaultRig);
  rig.projector_pose.translation = Eigen::Vector3d(1.000000000000001e-4, 0.0, 0.0);
  rig.camera.fx = 1492.0000000000002;
  rig.camera.dist[4] = 1e-300;
  rig.mount.rpy.z() = -M_PI / 7.0;
  rig.validate();
  const std::string yaml = rigToYaml(rig);
  Rig back;
  ASSERT_NO_THROW(back = parseRig(yaml, "round trip")) << yaml;
  EXPECT_EQ(back.projector_pose.translation, rig.projector_pose.translation);
  EXPECT_EQ(back.projector_pose.rotation, rig.projector_pose.rotation);
  EXPECT_EQ(back.camera.fx, rig.camera.fx);
  EXPECT_EQ(back.camera.dist, rig.camera.dist);
  EXPECT_EQ(back.mount.rpy, rig.mount.rpy);
  EXPECT_EQ(back.camera_optics.focus_distance, rig.camera_optics.focus_distance);
  EXPECT_EQ(back.projector_optics.f_number, rig.projector_optics.f_number);
  EXPECT_EQ(back.projector_optics.pixel_pitch, rig.projector_optics.pixel_pitch);
  EXPECT_NE(yaml.find("width: 752"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("D: [-0.08, 0.12, 5.0e-04, -3.0e-04, 1.0e-300]"), std::string::npos)
      << "an exponent keeps a '.' (a float to YAML 1.1 readers too):\n"
      << yaml;
  EXPECT_NE(yaml.find("rotation: [0.994001447, -0.0269034905,"), std::string::npos) << "short numbers stay short:\n"
                                                                                    << yaml;
}

// Found by fuzz/rig_parser_fuzz.cpp (corpus: parent_frame_binary_round_trip.yaml): a parent frame
// ending in control bytes and invalid UTF-8 was accepted, and rigToYaml() wrote another frame.
TEST(Rig, ParentFrameMustBeAFrameName)
{
  const std::string good = readFile(kDefaultRig);
  const std::string line = "parent_frame: platform_edge";
  const std::string binary = replaced(good, line, line + "\xff\xff" + "\x02");
  const std::string e = parseError(binary);
  EXPECT_NE(e.find("mount.parent_frame: must be a frame name (letters, digits, '_' and '/')"), std::string::npos) << e;
  EXPECT_NE(e.find("got 'platform_edge" + std::string(3, '?') + "'"), std::string::npos) << "bytes shown as '?': " << e;
  EXPECT_NE(parseError(replaced(good, line, "parent_frame: 'base link'")).find("mount.parent_frame"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, line, "parent_frame: ''")).find("mount.parent_frame"), std::string::npos);
  EXPECT_EQ(parseError(replaced(good, line, "parent_frame: /robot/base_link2")), "");
}

TEST(Rig, BadFilesNameTheKey)
{
  const std::string good = readFile(kDefaultRig);
  ASSERT_EQ(parseError(good), "");

  EXPECT_NE(parseError(replaced(good, "  width: 752\n", "")).find("camera.width: missing"), std::string::npos);
  EXPECT_NE(parseError(replaced(good, "[1492.0, 0.0, 372.0, 0.0, 1492.0, 243.0, 0.0, 0.0, 1.0]", "[1492.0, 0.0]"))
                .find("camera.K: has 2 numbers, expected 9"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, "rotation: [0.994001447", "rotation: [0.9"))
                .find("projector_pose.rotation: is not orthonormal"),
            std::string::npos);
  EXPECT_NE(
      parseError(replaced(good, "translation: [0.05524", "translation: [55.24")).find("projector_pose.translation"),
      std::string::npos);
  EXPECT_NE(parseError(replaced(good, "width: 752", "width: wide")).find("camera.width: cannot read 'wide'"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, "width: 752", "width: -752")).find("camera.width: must be > 0"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, "format_version: 1", "format_version: 7")).find("format_version"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, "cols: 64", "cols: 70")).find("pattern."), std::string::npos);
  EXPECT_NE(parseError(replaced(good, "D: [0.02", "D: [.nan")).find("projector.D"), std::string::npos);
  EXPECT_EQ(parseError(replaced(good, kPatternBlock, "")), "test.yaml: pattern: missing");
  EXPECT_NE(parseError("camera: [1, 2").find("not valid YAML"), std::string::npos);
  EXPECT_NE(parseError("").find("must be a mapping"), std::string::npos);
  EXPECT_NE(parseError(good + "depth_tables:\n  linear: {a: [1, 2], b: [1, 2], rms: [0, 0]}\n")
                .find("depth_tables.linear.a: has 2 numbers, expected 1024"),
            std::string::npos);

  try
  {
    loadRig("/nonexistent/rig.yaml");
    FAIL();
  }
  catch (const RigFileError& e)
  {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/rig.yaml: cannot open"), std::string::npos);
  }
  EXPECT_THROW(saveRig(loadRig(kDefaultRig), "/nonexistent/dir/rig.yaml"), RigFileError);
}

// Each lens's optics: optional keys of camera and projector, defaults of the devices, checked.
TEST(Rig, LensOpticsAreReadWithDefaultsAndChecked)
{
  const std::string good = readFile(kDefaultRig);
  const Rig rig = parseRig(good, "test.yaml");
  EXPECT_EQ(rig.camera_optics.focus_distance, 0.675);
  EXPECT_EQ(rig.camera_optics.f_number, 1.4);
  EXPECT_EQ(rig.camera_optics.pixel_pitch, 6.0e-6);
  EXPECT_EQ(rig.projector_optics.f_number, 1.8);
  EXPECT_EQ(rig.projector_optics.pixel_pitch, 7.6e-6);
  // A rig file without them (written before they existed) has the same optics.
  std::string old = good;
  for (const char* key : { "focus_distance", "f_number", "pixel_pitch" })
    for (int i = 0; i < 2; ++i)
    {
      const size_t at = old.find(std::string("  ") + key + ":");
      ASSERT_NE(at, std::string::npos) << key;
      old.erase(at, old.find('\n', at) + 1 - at);
    }
  const Rig defaults = parseRig(old, "old.yaml");
  EXPECT_EQ(defaults.camera_optics.focus_distance, rig.camera_optics.focus_distance);
  EXPECT_EQ(defaults.camera_optics.f_number, rig.camera_optics.f_number);
  EXPECT_EQ(defaults.projector_optics.focus_distance, rig.projector_optics.focus_distance);
  EXPECT_EQ(defaults.projector_optics.pixel_pitch, rig.projector_optics.pixel_pitch);
  // Another focus reads back; bad values name the key.
  EXPECT_EQ(parseRig(replaced(good, "focus_distance: 0.675", "focus_distance: 0.9"), "t").camera_optics.focus_distance,
            0.9);
  EXPECT_NE(parseError(replaced(good, "f_number: 1.4", "f_number: 0")).find("camera.f_number: must be in 0.5..64"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, "pixel_pitch: 7.6e-6", "pixel_pitch: 7.6")).find("projector.pixel_pitch"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, "focus_distance: 0.675", "focus_distance: 0.005"))
                .find("camera.focus_distance: must be in metres, beyond 1.5 focal lengths"),
            std::string::npos);
  EXPECT_NE(parseError(replaced(good, "f_number: 1.8", "f_number: fast")).find("projector.f_number: cannot read"),
            std::string::npos);
  // The thin lens: no blur at focus, more nearer than the same step in 1/z farther.
  const double f_px = rig.camera.fx;
  EXPECT_EQ(rig.camera_optics.defocusDiameter(f_px, 0.675), 0.0);
  EXPECT_GT(rig.camera_optics.defocusDiameter(f_px, 0.40), rig.camera_optics.defocusDiameter(f_px, 1.2));
  // 8.95 mm at f/1.4 focused at 0.675 m, a point at 0.45 m: 6.39 mm * 1492 * 1.0134 * 0.7407 / m = 7.16 px.
  EXPECT_NEAR(rig.camera_optics.defocusDiameter(f_px, 0.45), 7.16, 0.01);
}

// A 262144 x 262144 camera overflowed int in the decoder's table sizes and crashed sl_decode.
TEST(Rig, ImageSizesAreBounded)
{
  const std::string good = readFile(kDefaultRig);
  const std::string camera_size = "  width: 752\n  height: 480";
  for (const char* size : { "  width: 262144\n  height: 262144", "  width: 400000\n  height: 300000" })
  {
    const std::string text = replaced(good, camera_size, size);
    EXPECT_THROW(parseRig(text, "test.yaml"), RigFileError);
    const std::string error = parseError(text);
    EXPECT_EQ(error.rfind("test.yaml: camera.width: must be at most 16384 px", 0), 0u) << error;
  }
  // Each side within the limit, the area not.
  const std::string error = parseError(replaced(good, camera_size, "  width: 16384\n  height: 16384"));
  EXPECT_EQ(error.rfind("test.yaml: camera.width, camera.height: 16384 x 16384", 0), 0u) << error;
  // The largest allowed camera loads.
  EXPECT_EQ(parseError(replaced(good, camera_size, "  width: 16384\n  height: 4096")), "");
  // The projector is bounded as well (its frame is the pattern's).
  const std::string projector =
      parseError(replaced(good, "  width: 480\n  height: 320", "  width: 480\n  height: 262144"));
  EXPECT_EQ(projector.rfind("test.yaml: projector.height: must be at most 16384 px", 0), 0u) << projector;
}

TEST(Rig, TableSizesAreComputedWithoutOverflow)
{
  // The decoder's ray table of a 262144 px square camera: 65538 x 65538 cells, > INT_MAX.
  EXPECT_THROW(checkedCells(65538, 65538, "ray table"), std::invalid_argument);
  EXPECT_THROW(checkedCells(100002, 75002, "ray table"), std::invalid_argument);
  EXPECT_THROW(checkedCells(int64_t{ 1 } << 40, int64_t{ 1 } << 40, "ray table"), std::invalid_argument);
  EXPECT_THROW(checkedCells(0, 5, "ray table"), std::invalid_argument);
  EXPECT_EQ(checkedCells(190, 122, "ray table"), 23180u);
  EXPECT_EQ(checkedCells(16384, 4096, "image"), static_cast<size_t>(kMaxImagePixels));
  try
  {
    checkedCells(65538, 65538, "ray table");
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("ray table: 65538 x 65538 cells", 0), 0u) << e.what();
  }
}

// primitive_width 2147483647 with gap_x 1 passed validation and hung sl_decode.
TEST(Rig, HugePrimitiveSizesAreRefused)
{
  const std::string good = readFile(kDefaultRig);
  std::string text =
      replaced(replaced(good, "primitive_width: 5", "primitive_width: 2147483647"), "gap_x: 2", "gap_x: 1");
  EXPECT_THROW(parseRig(text, "test.yaml"), RigFileError);
  std::string error = parseError(text);
  EXPECT_EQ(error.rfind("test.yaml: pattern.primitive_width must be <= projector_width (480)", 0), 0u) << error;
  error = parseError(replaced(good, "gap_y: 6", "gap_y: 2147483647"));
  EXPECT_EQ(error.rfind("test.yaml: pattern.gap_y must be <= projector_height (320)", 0), 0u) << error;
}

// `mount: 1` and `depth_tables: 5` threw a raw YAML::BadSubscript naming neither file nor key.
TEST(Rig, WrongNodeTypesNameTheFileAndKey)
{
  const std::string good = readFile(kDefaultRig);
  const std::string mount =
      "mount:\n  parent_frame: platform_edge\n  xyz: [-0.030, 0.025, 0.0865]\n  rpy: [0.0, 0.0, -0.03702]";
  const std::string mount_1 = replaced(good, mount, "mount: 1");
  EXPECT_THROW(parseRig(mount_1, "test.yaml"), RigFileError);
  EXPECT_EQ(parseError(mount_1), "test.yaml: mount: must be a mapping");
  const std::string tables_5 = good + "depth_tables: 5\n";
  EXPECT_THROW(parseRig(tables_5, "test.yaml"), RigFileError);
  EXPECT_EQ(parseError(tables_5), "test.yaml: depth_tables: must be a mapping");
  EXPECT_EQ(parseError(replaced(good, mount, "mount: [1, 2]")), "test.yaml: mount: must be a mapping");
  EXPECT_EQ(parseError(good + "depth_tables: {linear: 3}\n"), "test.yaml: depth_tables.linear: must be a mapping");
  EXPECT_EQ(parseError(replaced(good, kPatternBlock, "pattern: 7\n")), "test.yaml: pattern: must be a mapping");
  EXPECT_EQ(parseError(replaced(good, kCameraK, "  K: {a: 1}")), "test.yaml: camera.K: must be a list of numbers");
}

// A misspelt optional key must not leave its default in place unnoticed: every mapping has its keys.
TEST(Rig, UnknownKeysAreRefusedNamingTheFileAndKey)
{
  const std::string good = readFile(kDefaultRig);
  EXPECT_EQ(parseError(good + "lens: 8.95\n"),
            "test.yaml: lens: unknown key (allowed: camera, depth_tables, format_version, mount, pattern, projector, "
            "projector_pose)");
  EXPECT_EQ(parseError(replaced(good, kPatternBlock, "patterns:" + kPatternBlock.substr(8))),
            "test.yaml: patterns: unknown key, did you mean 'pattern'? (allowed: camera, depth_tables, format_version, "
            "mount, pattern, projector, projector_pose)");
  EXPECT_EQ(parseError(replaced(good, kCameraK, "  Kx: [1, 0, 1, 0, 1, 1, 0, 0, 1]\n" + kCameraK)),
            "test.yaml: camera.Kx: unknown key, did you mean 'K'? (allowed: D, K, f_number, focus_distance, height, "
            "pixel_pitch, width)");
  EXPECT_EQ(
      parseError(replaced(good, "  flip_y: false", "  flipy: true"))
          .rfind("test.yaml: pattern.flipy: unknown key, did you mean 'flip_y'? (allowed: cols, flip_x, flip_y, ", 0),
      0u);
  EXPECT_EQ(parseError(replaced(good, "  xyz: [", "  xzy: [")),
            "test.yaml: mount.xzy: unknown key, did you mean 'xyz'? (allowed: parent_frame, rpy, xyz)");
  EXPECT_EQ(parseError(replaced(good, "  translation: [", "  offset: [0, 0, 0]\n  translation: [")),
            "test.yaml: projector_pose.offset: unknown key (allowed: rotation, translation)");
  EXPECT_EQ(parseError(replaced(good, "  width: 480", "  width: 480\n  camera_name: dlp"))
                .rfind("test.yaml: projector.camera_name: unknown key", 0),
            0u);
  EXPECT_EQ(parseError(good + "depth_tables:\n  distance: [0.5]\n"),
            "test.yaml: depth_tables.distance: unknown key, did you mean 'distances'? (allowed: distances, linear, "
            "rational)");
  // The linear model has no c; the keys are checked before the 1024 numbers are read.
  EXPECT_EQ(parseError(good + "depth_tables:\n  linear: {a: [], b: [], c: [], rms: []}\n"),
            "test.yaml: depth_tables.linear.c: unknown key (allowed: a, b, rms)");
  EXPECT_EQ(parseError(good + "? [1]\n: 2\n"),
            "test.yaml: [1]: a key must be a name, not a list or a mapping (line 62)");

  // From a file: the message starts with its path.
  const std::string path = ::testing::TempDir() + "/sl_rig_unknown_key.yaml";
  std::ofstream(path) << replaced(good, "  gap_x: 2", "  gapx: 2");
  try
  {
    loadRig(path);
    FAIL() << "gapx accepted";
  }
  catch (const RigFileError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": pattern.gapx: unknown key, did you mean 'gap_x'?", 0), 0u)
        << e.what();
  }
  std::remove(path.c_str());
}

// Every rig file of the repository loads: the configurations, the tests' rigs and the fuzzers' seeds
// (a rig file is a YAML file with `projector_pose:`). Only the seed that is refused on purpose is not.
TEST(Rig, EveryRigFileOfTheRepositoryLoads)
{
  namespace fs = std::filesystem;
  const std::set<std::string> refused = { "parent_frame_binary_round_trip.yaml" };  // control bytes in a frame name
  std::vector<std::string> loaded;
  const fs::path root(SL_RIG_REPOSITORY_DIR);
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it)
  {
    const fs::path& p = it->path();
    if (it->is_directory() && (p.filename() == ".git" || p.filename() == "catkin_ws"))
    {
      it.disable_recursion_pending();  // build trees and the workspace's links to the packages
      continue;
    }
    if (!it->is_regular_file() || p.extension() != ".yaml" ||
        readFile(p.string()).find("projector_pose:") == std::string::npos)
      continue;
    if (refused.count(p.filename().string()))
    {
      EXPECT_THROW(loadRig(p.string()), RigFileError) << p;
      continue;
    }
    EXPECT_NO_THROW(loadRig(p.string())) << p;
    loaded.push_back(p.lexically_relative(root).string());
  }
  std::string list;
  for (const std::string& f : loaded)
    list += "  " + f + "\n";
  std::cout << loaded.size() << " rig files loaded:\n" << list;
  // Measured: 12 (sl_projector/config, sl_evaluation/test/rigs, fuzz/corpus/rig_parser and decoder_rig).
  EXPECT_GE(loaded.size(), 12u);
  EXPECT_NE(list.find("sl_projector/config/default_rig.yaml"), std::string::npos) << list;
  EXPECT_NE(list.find("sl_evaluation/test/rigs/second_rig.yaml"), std::string::npos) << list;
}
