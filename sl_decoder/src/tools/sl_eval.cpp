// sl_eval: renders the prototype's test scenes with the simulator, decodes them with every depth
// model the rig supports and prints a table against the ground truth. No ROS master needed.
#include <algorithm>
#include <cstdio>
#include <dirent.h>
#include <iostream>
#include <string>
#include <vector>

#include "sl_decoder/evaluation.h"

namespace
{
const char* kUsage =
    "usage: sl_eval [--calibration RIG.yaml] [--frames N] [--ambient X] [SCENE.yaml ...]\n"
    "  renders each scene (default: the prototype's test scenes in sl_camera/scenes) with the simulator's\n"
    "  default settings, decodes it with every depth model the rig supports, and prints per scene:\n"
    "  visible primitives, valid %, wrong correspondences, mean and max |depth error| (mm), and the\n"
    "  points on objects in front of the background.\n";

std::vector<std::string> defaultScenes()
{
  std::vector<std::string> out;
  const std::string dir = sl_decoder::defaultScenesDir();
  DIR* d = opendir(dir.c_str());
  if (!d)
    throw std::runtime_error("cannot open the scenes directory " + dir);
  while (dirent* e = readdir(d))
  {
    const std::string name = e->d_name;
    // The prototype's test scenes: not the room (closed-loop demo) nor the calibration boards.
    if (name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0 && name.find("room") == std::string::npos &&
        name.find("checkerboard") == std::string::npos && name.rfind("calib", 0) != 0)
      out.push_back(dir + "/" + name);
  }
  closedir(d);
  std::sort(out.begin(), out.end());
  return out;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string calibration = sl_decoder::defaultRigFile();
  int frames = 3;
  sl_camera::SimSettings settings;
  std::vector<std::string> scenes;
  try
  {
    for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc)
          throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--calibration")
        calibration = next();
      else if (a == "--frames")
        frames = std::max(1, std::stoi(next()));
      else if (a == "--ambient")
        settings.ambient = std::stod(next());
      else if (a == "-h" || a == "--help")
      {
        std::cout << kUsage;
        return 0;
      }
      else if (!a.empty() && a[0] == '-')
        throw std::invalid_argument("unknown option '" + a + "'");
      else
        scenes.push_back(a);
    }
    if (scenes.empty())
      scenes = defaultScenes();
    const sl_projector::Rig rig = sl_projector::loadRig(calibration);
    std::vector<sl_decoder::DepthMode> models{ sl_decoder::DepthMode::Triangulation };
    if (!rig.tables.rational.empty())
      models.push_back(sl_decoder::DepthMode::Rational);
    if (!rig.tables.linear.empty())
      models.push_back(sl_decoder::DepthMode::Linear);

    std::printf("%-22s %-13s %7s %7s %6s %6s %9s %8s %8s\n", "scene", "model", "visible", "valid%", "extra", "wrong",
                "mean_mm", "max_mm", "near_pts");
    sl_decoder::EvalStats total;
    for (const std::string& scene : scenes)
      for (sl_decoder::DepthMode model : models)
      {
        sl_decoder::DecoderConfig config;
        config.depth_mode = model;
        const sl_decoder::SceneReport r = sl_decoder::evaluateScene(rig, scene, config, frames, settings);
        const sl_decoder::EvalStats& s = r.stats;
        std::printf("%-22s %-13s %7.1f %7.1f %6.1f %6d %9.2f %8.2f %8.1f\n", r.scene.c_str(), r.model.c_str(),
                    static_cast<double>(s.visible) / s.frames, s.validPercent(),
                    static_cast<double>(s.valid - s.valid_visible) / s.frames, s.wrong, s.meanErrorMm(),
                    s.maxErrorMm(), static_cast<double>(s.near_points) / s.frames);
        if (model == sl_decoder::DepthMode::Triangulation)
          total.add(s);
      }
    std::printf("all scenes (triangulation): %d frames, %d points, %d wrong, %d unverifiable\n", total.frames,
                total.valid, total.wrong, total.unverifiable);
  }
  catch (const std::exception& e)
  {
    std::cerr << "sl_eval: " << e.what() << "\n" << kUsage;
    return 2;
  }
  return 0;
}
