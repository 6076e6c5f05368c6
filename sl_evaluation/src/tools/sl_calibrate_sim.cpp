// sl_calibrate_sim: the calibration procedure in simulation. `render` writes the images a user
// would record (the wall at known distances, checkerboard views, calibration plane poses) and prints
// the calibration commands; `evaluate` measures a calibration file against the simulator's true rig.
// No ROS master needed.
#include <cerrno>
#include <cstdio>
#include <iostream>
#include <string>
#include <sys/stat.h>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "sl_calibration/full_calibration.h"
#include "sl_evaluation/calibration_simulation.h"
#include "sl_rig/tool_args.h"

namespace
{
using namespace sl_decoder;
using namespace sl_calibration;
using namespace sl_evaluation;

const char* kUsage =
    "usage: sl_calibrate_sim render --out-dir DIR [options]\n"
    "       sl_calibrate_sim evaluate --calibration CAL.yaml [options]\n"
    "render: writes the calibration images of the simulator's true rig into DIR:\n"
    "  DIR/plane/wall_<mm>_<frame>.png   pattern on the wall (calib_wall.yaml) at each distance\n"
    "  DIR/board/<scene>.png             checkerboard views for the camera (calib_board_*.yaml)\n"
    "  DIR/pose/<scene>_board.png        calibration plane poses (calib_plane_*.yaml): board image\n"
    "  DIR/pose/<scene>_pattern.png      ... and pattern image (board covered)\n"
    "  and prints the sl_calibrate_plane and sl_calibrate_full commands that calibrate from them.\n"
    "evaluate: renders the wall at distances not used for calibration, decodes with every depth model\n"
    "  CAL.yaml has (rational, linear tables; triangulation) and prints the mean |depth error| per\n"
    "  distance; compares CAL.yaml's camera, projector and pose with the true rig; compares depth from\n"
    "  CAL.yaml with depth from the true rig on the wall at 0.7 m.\n"
    "options:\n"
    "  --rig FILE            the true rig (default: sl_projector/config/default_rig.yaml)\n"
    "  --scenes-dir DIR      where the calib_*.yaml scenes are (default: sl_sim/scenes)\n"
    "  --distances LIST      render: 0.5,0.6,0.7,0.8,0.9   evaluate: 0.55,0.65,0.75,0.85 (m, camera\n"
    "                        centre to wall along the robot's x axis)\n"
    "  --frames N            images per distance (default 1)\n"
    "  --seed N              first noise seed (default 1)\n"
    "  --ambient X           ambient light of the pattern images (simulator setting)\n"
    "  --board-ambient X     ambient light of the board images, lights on (default 0.6)\n";

int fail(const std::string& message)
{
  std::cerr << "sl_calibrate_sim: " << message << "\n";
  return 1;
}

void makeDir(const std::string& path)
{
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST)
    throw CalibrationError(path + ": cannot create the folder");
}

void write(const std::string& path, const cv::Mat& image)
{
  if (!cv::imwrite(path, image))
    throw CalibrationError(path + ": cannot write the image");
}

std::string stem(const std::string& path)
{
  const size_t slash = path.find_last_of('/');
  std::string s = slash == std::string::npos ? path : path.substr(slash + 1);
  if (s.size() > 5 && s.compare(s.size() - 5, 5, ".yaml") == 0)
    s.resize(s.size() - 5);
  return s;
}

std::string mmName(double d)
{
  char b[32];
  std::snprintf(b, sizeof(b), "%04d", static_cast<int>(std::lround(d * 1000.0)));
  return b;
}
}  // namespace

int main(int argc, char** argv)
{
  if (argc < 2 || std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help")
  {
    std::cout << kUsage;
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  std::string rig_path = defaultRigFile(), out_dir, calibration, scenes_dir;
  std::vector<double> distances;
  int frames = 1;
  uint64_t seed = 1;
  sl_sim::SimSettings settings;
  double board_ambient = 0.6;
  try
  {
    sl_rig::ToolArgs args(argc, argv, 2);  // after the command
    for (std::string a; args.next(a);)
    {
      if (a == "--rig")
        rig_path = args.value();
      else if (a == "--out-dir")
        out_dir = args.value();
      else if (a == "--calibration")
        calibration = args.value();
      else if (a == "--scenes-dir")
        scenes_dir = args.value();
      else if (a == "--distances")
        distances = parseNumberList(args.value());
      else if (a == "--frames")
        frames = static_cast<int>(args.integer(1, 100));
      else if (a == "--seed")
        seed = static_cast<uint64_t>(args.integer(0));
      else if (a == "--ambient")
        settings.ambient = args.number();
      else if (a == "--board-ambient")
        board_ambient = args.number();
      else
        args.unknown();
    }
    if (frames < 1 || frames > 100)
      throw std::invalid_argument("--frames must be 1..100");
    settings.validate();
  }
  catch (const std::exception& e)
  {
    std::cerr << "sl_calibrate_sim: " << e.what() << "\n" << kUsage;
    return 2;
  }

  try
  {
    const sl_projector::Rig rig = sl_projector::loadRig(rig_path);
    const SimScenes scenes = findSimScenes(scenes_dir);
    const sl_sim::Scene wall = sl_sim::loadScene(scenes.wall);
    PlaneCalibrationOptions plane_options;
    CalibrationSimulator sim(rig, settings, board_ambient);

    if (command == "render")
    {
      if (out_dir.empty())
        throw std::invalid_argument("render: --out-dir is required");
      if (distances.empty())
        distances = { 0.5, 0.6, 0.7, 0.8, 0.9 };
      makeDir(out_dir);
      makeDir(out_dir + "/plane");
      makeDir(out_dir + "/board");
      makeDir(out_dir + "/pose");
      std::string plane_args;
      for (double d : distances)
        for (int f = 0; f < frames; ++f)
        {
          const std::string name = out_dir + "/plane/wall_" + mmName(d) + "_" + std::to_string(f) + ".png";
          write(name, sim.renderWall(wall, d, plane_options, seed++).image);
          plane_args += " " + name + ":" + fixed(d, 3);
        }
      std::string board_args, pose_args;
      Board board;
      bool have_board = false;
      for (const std::string& path : scenes.boards)
      {
        const sl_sim::Scene scene = sl_sim::loadScene(path);
        const std::string name = out_dir + "/board/" + stem(path) + ".png";
        write(name, sim.renderBoard(scene, seed++).image);
        board_args += " --camera-view " + name;
      }
      for (const std::string& path : scenes.planes)
      {
        const sl_sim::Scene scene = sl_sim::loadScene(path);
        if (!have_board)
        {
          board = boardOfScene(scene);
          have_board = true;
        }
        const std::string board_name = out_dir + "/pose/" + stem(path) + "_board.png";
        const std::string pattern_name = out_dir + "/pose/" + stem(path) + "_pattern.png";
        write(board_name, sim.renderBoard(scene, seed++).image);
        const sl_sim::Scene covered = withoutTextures(scene);
        write(pattern_name, sim.renderPattern(covered, Eigen::Isometry3d::Identity(), seed++).image);
        pose_args += " --pose " + board_name + "," + pattern_name;
      }
      std::cout << "wrote the calibration images to " << out_dir << "\n\n"
                << "plane calibration:\n  rosrun sl_calibration sl_calibrate_plane --rig " << rig_path << " --out "
                << out_dir << "/plane_calibrated.yaml" << plane_args << "\n\n"
                << "full calibration:\n  rosrun sl_calibration sl_calibrate_full --rig " << out_dir
                << "/plane_calibrated.yaml --out " << out_dir << "/calibrated.yaml --board " << board.cols << "x"
                << board.rows << " --square " << board.square << board_args << pose_args << "\n\n"
                << "evaluation:\n  rosrun sl_evaluation sl_calibrate_sim evaluate --calibration " << out_dir
                << "/calibrated.yaml" << (rig_path == defaultRigFile() ? "" : " --rig " + rig_path) << "\n";
      return 0;
    }
    if (command == "evaluate")
    {
      if (calibration.empty())
        throw std::invalid_argument("evaluate: --calibration is required");
      if (distances.empty())
        distances = { 0.55, 0.65, 0.75, 0.85 };
      const sl_projector::Rig cal = sl_projector::loadRig(calibration);
      std::vector<std::pair<std::string, DepthMode>> models;
      if (!cal.tables.rational.empty())
        models.emplace_back("rational", DepthMode::Rational);
      if (!cal.tables.linear.empty())
        models.emplace_back("linear", DepthMode::Linear);
      models.emplace_back("triangulation", DepthMode::Triangulation);
      std::printf("mean |depth error| (mm) of %s on the wall at distances not used for calibration, %d frame(s) each\n",
                  calibration.c_str(), frames);
      std::printf("%-12s", "distance_m");
      for (const auto& m : models)
        std::printf(" %14s", m.first.c_str());
      std::printf("\n");
      std::vector<EvalStats> totals(models.size());
      for (double d : distances)
      {
        std::vector<EvalStats> row(models.size());
        for (int f = 0; f < frames; ++f)
        {
          const sl_sim::RenderOutput& truth = sim.renderWall(wall, d, plane_options, 5000 + seed + f);
          for (size_t k = 0; k < models.size(); ++k)
            row[k].add(evaluateRendered(cal, models[k].second, truth));
        }
        std::printf("%-12.3f", d);
        for (size_t k = 0; k < models.size(); ++k)
        {
          std::printf(" %14.3f", row[k].meanErrorMm());
          totals[k].add(row[k]);
        }
        std::printf("\n");
      }
      std::printf("%-12s", "all");
      for (const EvalStats& t : totals)
        std::printf(" %14.3f", t.meanErrorMm());
      std::printf("\n%-12s", "points");
      for (const EvalStats& t : totals)
        std::printf(" %14d", t.with_depth);
      std::printf("\n\ncalibration against the true rig (%s):\n%s", rig_path.c_str(),
                  compareRigs(cal, rig).summary().c_str());
      const sl_sim::RenderOutput& at700 = sim.renderWall(wall, 0.7, plane_options, 9000 + seed);
      const DepthAgreement agree = compareDepth(cal, rig, at700.image);
      std::printf(
          "depth (triangulation) from %s vs the true rig on the wall at 0.700 m: mean |difference| %.3f mm, "
          "max %.3f mm over %d primitives\n",
          calibration.c_str(), agree.mean_mm, agree.max_mm, agree.points);
      return 0;
    }
    throw std::invalid_argument("unknown command '" + command + "' (render or evaluate)");
  }
  catch (const std::invalid_argument& e)
  {
    std::cerr << "sl_calibrate_sim: " << e.what() << "\n" << kUsage;
    return 2;
  }
  catch (const std::exception& e)
  {
    return fail(e.what());
  }
}
