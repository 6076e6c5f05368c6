// sl_eval: renders the prototype's test scenes with the simulator, decodes them with every depth
// model the rig supports and prints a table against the ground truth. No ROS master needed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <dirent.h>
#include <iostream>
#include <string>
#include <vector>

#include "sl_evaluation/evaluation.h"
#include "sl_projector/tool_args.h"

namespace
{
const char* kUsage =
    "usage: sl_eval [--calibration RIG.yaml] [--frames N] [--seed N] [--ambient X] [--set NAME=VALUE ...]\n"
    "               [--plane DIST ...] [SCENE.yaml ...]\n"
    "  renders each scene (default: the prototype's test scenes in sl_sim/scenes, then the near-range\n"
    "  planes) with the simulator's settings, decodes it with every depth model the rig supports, and\n"
    "  prints per scene: visible primitives, valid %, wrong correspondences, mean and max |depth error|\n"
    "  (mm), and the points on objects in front of the background.\n"
    "  --plane DIST   a white plane DIST m from the camera (repeatable; instead of the default scenes)\n"
    "  --albedo A     albedo of those planes (default 0.8)\n"
    "  --no-split-merged  decode with the near-range detection off (DecoderConfig::split_merged)\n"
    "  --set N=V      a simulator setting, as in sl_render (repeatable)\n"
    "  --seed N       noise seed of the first frame (default 1000)\n"
    "  Near-range rows (default run): planes at 0.35, 0.40 and 0.45 m, and 0.45 m with\n"
    "  projector_f_number=0.9 (twice the projector's defocus blur).\n";

std::vector<std::string> defaultScenes()
{
  std::vector<std::string> out;
  const std::string dir = sl_evaluation::defaultScenesDir();
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

/// One scene to evaluate: a file, or a plane built in code, with its simulator settings.
struct Job
{
  std::string file;    // empty for a plane
  double plane = 0.0;  // m from the camera
  sl_sim::SimSettings settings;
  std::string name;
};

void setSetting(sl_sim::SimSettings& settings, const std::string& text)
{
  const size_t eq = text.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument("--set needs NAME=VALUE, got '" + text + "'");
  std::string v = text.substr(eq + 1);
  if (v == "true")
    v = "1";
  else if (v == "false")
    v = "0";
  size_t used = 0;
  const double x = std::stod(v, &used);
  if (used != v.size())
    throw std::invalid_argument("--set " + text.substr(0, eq) + ": not a number: '" + v + "'");
  sl_sim::setSimSetting(settings, text.substr(0, eq), x);
}

std::string planeName(double d, const char* suffix = "")
{
  char buf[64];
  std::snprintf(buf, sizeof(buf), "near_plane_%03d%s", static_cast<int>(std::lround(d * 1000.0)), suffix);
  return buf;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string calibration = sl_evaluation::defaultRigFile();
  int frames = 3;
  uint64_t seed = 1000;
  sl_sim::SimSettings settings;
  std::vector<std::string> scenes;
  std::vector<double> planes;
  double albedo = 0.8;
  bool split_merged = sl_decoder::DecoderConfig().split_merged;
  try
  {
    sl_projector::ToolArgs args(argc, argv);
    for (std::string a; args.next(a);)
    {
      if (a == "--calibration")
        calibration = args.value();
      else if (a == "--frames")
        frames = static_cast<int>(args.integer(1, 1000000));
      else if (a == "--ambient")
        settings.ambient = args.number();
      else if (a == "--set")
        setSetting(settings, args.value());
      else if (a == "--seed")
        seed = static_cast<uint64_t>(args.integer(0));
      else if (a == "--no-split-merged")
        split_merged = false;
      else if (a == "--albedo")
      {
        albedo = args.number();
        if (!(albedo > 0.0 && albedo <= 1.0))
          throw std::invalid_argument("--albedo: must be in (0, 1]");
      }
      else if (a == "--plane")
      {
        const double d = args.number();
        if (!(d >= 0.2 && d <= 3.0))
          throw std::invalid_argument("--plane: distance must be 0.2 to 3 m");
        planes.push_back(d);
      }
      else if (a == "-h" || a == "--help")
      {
        std::cout << kUsage;
        return 0;
      }
      else if (!a.empty() && a[0] == '-')
        args.unknown();
      else
        scenes.push_back(a);
    }
    std::vector<Job> jobs;
    for (const std::string& f : scenes)
      jobs.push_back(Job{ f, 0.0, settings, "" });
    for (double d : planes)
      jobs.push_back(Job{ "", d, settings, planeName(d) });
    if (jobs.empty())
    {
      for (const std::string& f : defaultScenes())
        jobs.push_back(Job{ f, 0.0, settings, "" });
      for (double d : { 0.35, 0.40, 0.45 })
        jobs.push_back(Job{ "", d, settings, planeName(d) });
      Job blurred{ "", 0.45, settings, planeName(0.45, "_f0.9") };
      blurred.settings.projector_f_number = 0.9;
      jobs.push_back(blurred);
    }
    const sl_projector::Rig rig = sl_projector::loadRig(calibration);
    std::vector<sl_decoder::DepthMode> models{ sl_decoder::DepthMode::Triangulation };
    if (!rig.tables.rational.empty())
      models.push_back(sl_decoder::DepthMode::Rational);
    if (!rig.tables.linear.empty())
      models.push_back(sl_decoder::DepthMode::Linear);

    std::printf("%-26s %-13s %7s %7s %6s %6s %9s %8s %8s\n", "scene", "model", "visible", "valid%", "extra", "wrong",
                "mean_mm", "max_mm", "near_pts");
    sl_evaluation::EvalStats total;
    for (const Job& job : jobs)
      for (sl_decoder::DepthMode model : models)
      {
        sl_decoder::DecoderConfig config;
        config.depth_mode = model;
        config.split_merged = split_merged;
        const sl_sim::Scene scene =
            job.file.empty() ? sl_evaluation::planeScene(rig, job.plane, albedo) : sl_sim::loadScene(job.file);
        const std::string name = job.file.empty() ? job.name : sl_evaluation::sceneStem(job.file);
        const sl_evaluation::SceneReport r =
            sl_evaluation::evaluateScene(rig, scene, name, config, frames, job.settings, seed);
        const sl_evaluation::EvalStats& s = r.stats;
        std::printf("%-26s %-13s %7.1f %7.1f %6.1f %6d %9.2f %8.2f %8.1f\n", r.scene.c_str(), r.model.c_str(),
                    static_cast<double>(s.visible) / s.frames, s.validPercent(),
                    static_cast<double>(s.valid - s.valid_visible) / s.frames, s.wrong, s.meanErrorMm(), s.maxErrorMm(),
                    static_cast<double>(s.near_points) / s.frames);
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
