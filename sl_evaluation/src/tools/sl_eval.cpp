// sl_eval: renders the prototype's test scenes (or planes) with the simulator for a rig file, decodes
// them with every depth model the rig supports and prints a table against the ground truth, with the
// decode time; --plot draws valid % and depth error against distance as PNG. No ROS master needed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <dirent.h>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "sl_evaluation/evaluation.h"
#include "sl_evaluation/plot.h"
#include "sl_rig/tool_args.h"

namespace
{
const char* kUsage =
    "usage: sl_eval [--rig RIG.yaml] [--frames N] [--seed N] [--ambient X] [--set NAME=VALUE ...]\n"
    "               [--defocus-scale S] [--plane DIST ... | --near-far] [--plot FILE.png] [SCENE.yaml ...]\n"
    "  renders each scene (default: the prototype's test scenes in sl_sim/scenes, then the near-range\n"
    "  planes) with the simulator's settings, decodes it with every depth model the rig supports, and\n"
    "  prints per scene: visible primitives, valid %, wrong correspondences, mean and max |depth error|\n"
    "  (mm), the points on objects in front of the background and the median decode time per frame\n"
    "  (dec_ms; wall clock, one thread, after one untimed warm-up decode).\n"
    "  --rig RIG.yaml the rig (calibration) file that renders and decodes (default: the default rig);\n"
    "                 --calibration is the same option\n"
    "  --plane DIST   a white plane DIST m from the camera (repeatable; instead of the default scenes)\n"
    "  --near-far     planes at 0.35, 0.40, 0.45 m (near range) and 0.55, 0.70, 0.90, 1.20 m, placed\n"
    "                 from the rig's camera (instead of the default scenes)\n"
    "  --defocus-scale S  both lenses' defocus blur times S, 0.1 to 4 (the simulator's defocus_scale:\n"
    "                 lenses unlike the rig file's optics)\n"
    "  --albedo A     albedo of those planes (default 0.8)\n"
    "  --no-split-merged  decode with the near-range detection off (DecoderConfig::split_merged)\n"
    "  --set N=V      a simulator setting, as in sl_render (repeatable)\n"
    "  --seed N       noise seed of the first frame (default 1000)\n"
    "  --plot FILE.png  also draw valid % and |depth error| (mean, 95th percentile, max) against distance\n"
    "                 (triangulation) for the planes: --plane DIST, scene files plane_<mm>.yaml, the\n"
    "                 default near-range planes\n"
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
  double distance = std::numeric_limits<double>::quiet_NaN();  // m from the camera, for the plot; NaN: not plotted
};

struct Options
{
  std::string calibration = sl_evaluation::defaultRigFile();
  bool near_far = false;
  int frames = 3;
  uint64_t seed = 1000;
  sl_sim::SimSettings settings;
  std::vector<std::string> scenes;
  std::vector<double> planes;
  double albedo = 0.8;
  bool split_merged = sl_decoder::DecoderConfig().split_merged;
  std::string plot;  // PNG file; empty: no chart
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

/// The distance of a scene file named plane_<mm>.yaml (a white plane <mm> from the camera), or NaN.
double sceneFileDistance(const std::string& file)
{
  const std::string stem = sl_evaluation::sceneStem(file);
  const std::string digits = stem.size() > 6 && stem.rfind("plane_", 0) == 0 ? stem.substr(6) : "";
  if (digits.empty() || digits.size() > 5 || digits.find_first_not_of("0123456789") != std::string::npos)
    return std::numeric_limits<double>::quiet_NaN();
  return std::stoi(digits) / 1000.0;
}

/// Reads the options; false for --help (the usage printed).
bool parseOptions(int argc, char** argv, Options& o)
{
  sl_rig::ToolArgs args(argc, argv);
  for (std::string a; args.next(a);)
  {
    if (a == "--calibration" || a == "--rig")
      o.calibration = args.value();
    else if (a == "--defocus-scale")
    {
      o.settings.defocus_scale = args.number();
      if (!(o.settings.defocus_scale >= 0.1 && o.settings.defocus_scale <= 4.0))
        throw std::invalid_argument("--defocus-scale: must be 0.1 to 4");
    }
    else if (a == "--near-far")
      o.near_far = true;
    else if (a == "--frames")
      o.frames = static_cast<int>(args.integer(1, 1000000));
    else if (a == "--ambient")
      o.settings.ambient = args.number();
    else if (a == "--set")
      setSetting(o.settings, args.value());
    else if (a == "--seed")
      o.seed = static_cast<uint64_t>(args.integer(0));
    else if (a == "--no-split-merged")
      o.split_merged = false;
    else if (a == "--albedo")
    {
      o.albedo = args.number();
      if (!(o.albedo > 0.0 && o.albedo <= 1.0))
        throw std::invalid_argument("--albedo: must be in (0, 1]");
    }
    else if (a == "--plane")
    {
      const double d = args.number();
      if (!(d >= 0.2 && d <= 3.0))
        throw std::invalid_argument("--plane: distance must be 0.2 to 3 m");
      o.planes.push_back(d);
    }
    else if (a == "--plot")
      o.plot = args.value();
    else if (a == "-h" || a == "--help")
    {
      std::cout << kUsage;
      return false;
    }
    else if (!a.empty() && a[0] == '-')
      args.unknown();
    else
      o.scenes.push_back(a);
  }
  if (o.near_far)
    o.planes.insert(o.planes.end(), sl_evaluation::nearFarDistances().begin(), sl_evaluation::nearFarDistances().end());
  return true;
}

std::vector<Job> makeJobs(const Options& o)
{
  std::vector<Job> jobs;
  std::vector<std::string> files = o.scenes;
  if (o.scenes.empty() && o.planes.empty())
    files = defaultScenes();
  for (const std::string& f : files)
    jobs.push_back(Job{ f, 0.0, o.settings, sl_evaluation::sceneStem(f), sceneFileDistance(f) });
  for (double d : o.planes)
    jobs.push_back(Job{ "", d, o.settings, planeName(d), d });
  if (o.scenes.empty() && o.planes.empty())
  {
    for (double d : { 0.35, 0.40, 0.45 })
      jobs.push_back(Job{ "", d, o.settings, planeName(d), d });
    Job blurred{ "", 0.45, o.settings, planeName(0.45, "_f0.9") };  // other settings: not plotted
    blurred.settings.projector_f_number = 0.9;
    jobs.push_back(blurred);
  }
  return jobs;
}

std::vector<sl_decoder::DepthMode> depthModels(const sl_projector::Rig& rig)
{
  std::vector<sl_decoder::DepthMode> models{ sl_decoder::DepthMode::Triangulation };
  if (!rig.tables.rational.empty())
    models.push_back(sl_decoder::DepthMode::Rational);
  if (!rig.tables.linear.empty())
    models.push_back(sl_decoder::DepthMode::Linear);
  return models;
}

void printRow(const sl_evaluation::SceneReport& r)
{
  const sl_evaluation::EvalStats& s = r.stats;
  std::printf("%-26s %-13s %7.1f %7.1f %6.1f %6d %9.2f %8.2f %8.1f %7.2f\n", r.scene.c_str(), r.model.c_str(),
              static_cast<double>(s.visible) / s.frames, s.validPercent(),
              static_cast<double>(s.valid - s.valid_visible) / s.frames, s.wrong, s.meanErrorMm(), s.maxErrorMm(),
              static_cast<double>(s.near_points) / s.frames, s.decodeMs());
  std::fflush(stdout);
}

/// Evaluates every job with every model, prints the table (stdout) and a progress line per job
/// (stderr); returns the triangulation results of the jobs at a distance.
std::vector<sl_evaluation::DistanceResult> runJobs(const Options& o, const std::vector<Job>& jobs,
                                                   const sl_projector::Rig& rig)
{
  const std::vector<sl_decoder::DepthMode> models = depthModels(rig);
  std::vector<sl_evaluation::DistanceResult> plotted;
  std::printf("%-26s %-13s %7s %7s %6s %6s %9s %8s %8s %7s\n", "scene", "model", "visible", "valid%", "extra", "wrong",
              "mean_mm", "max_mm", "near_pts", "dec_ms");
  sl_evaluation::EvalStats total;
  for (size_t j = 0; j < jobs.size(); ++j)
  {
    const Job& job = jobs[j];
    std::fprintf(stderr, "sl_eval: scene %zu of %zu: %s", j + 1, jobs.size(), job.name.c_str());
    if (std::isfinite(job.distance))
      std::fprintf(stderr, " (%.2f m)", job.distance);
    if (o.frames == 1)
      std::fprintf(stderr, ", seed %llu", static_cast<unsigned long long>(o.seed));
    else
      std::fprintf(stderr, ", seeds %llu..%llu", static_cast<unsigned long long>(o.seed),
                   static_cast<unsigned long long>(o.seed) + static_cast<unsigned long long>(o.frames - 1));
    for (size_t m = 0; m < models.size(); ++m)
      std::fprintf(stderr, "%s%s", m == 0 ? ", " : "+", sl_decoder::depthModeName(models[m]));
    std::fprintf(stderr, " ...");
    const auto start = std::chrono::steady_clock::now();
    const sl_sim::Scene scene =
        job.file.empty() ? sl_evaluation::planeScene(rig, job.plane, o.albedo) : sl_sim::loadScene(job.file);
    std::vector<sl_evaluation::SceneReport> reports;
    for (sl_decoder::DepthMode model : models)
    {
      sl_decoder::DecoderConfig config;
      config.depth_mode = model;
      config.split_merged = o.split_merged;
      reports.push_back(sl_evaluation::evaluateScene(rig, scene, job.name, config, o.frames, job.settings, o.seed));
    }
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    std::fprintf(stderr, " done in %.1f s\n", took.count());
    for (const sl_evaluation::SceneReport& r : reports)
      printRow(r);
    // The first model is triangulation.
    total.add(reports.front().stats);
    if (std::isfinite(job.distance))
      plotted.push_back(sl_evaluation::DistanceResult{ job.distance, reports.front().stats });
  }
  std::printf("all scenes (triangulation): %d frames, %d points, %d wrong, %d unverifiable\n", total.frames,
              total.valid, total.wrong, total.unverifiable);
  std::fflush(stdout);
  return plotted;
}
}  // namespace

int main(int argc, char** argv)
{
  try
  {
    Options o;
    if (!parseOptions(argc, argv, o))
      return 0;
    const std::vector<Job> jobs = makeJobs(o);
    if (!o.plot.empty())
    {
      // Before the run: a bad file name or nothing to plot fails at once.
      try
      {
        sl_evaluation::checkChartPath(o.plot);
      }
      catch (const std::exception& e)
      {
        throw std::invalid_argument(std::string("--plot: ") + e.what());
      }
      if (std::none_of(jobs.begin(), jobs.end(), [](const Job& j) { return std::isfinite(j.distance); }))
        throw std::invalid_argument(
            "--plot: no plane at a known distance among the scenes (--plane DIST, "
            "plane_<mm>.yaml)");
    }
    const sl_projector::Rig rig = sl_projector::loadRig(o.calibration);
    const std::vector<sl_evaluation::DistanceResult> plotted = runJobs(o, jobs, rig);
    if (!o.plot.empty())
    {
      const std::string title = "Decoding against distance: " + sl_evaluation::sceneStem(o.calibration) + ", " +
                                std::to_string(o.frames) + " frames each, triangulation";
      try
      {
        sl_evaluation::writeChart(sl_evaluation::decodingChart(plotted, title), o.plot);
      }
      catch (const std::exception& e)
      {
        throw std::runtime_error(std::string("--plot: ") + e.what());
      }
      std::fprintf(stderr, "sl_eval: wrote %s (%zu distances)\n", o.plot.c_str(), plotted.size());
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "sl_eval: " << e.what() << "\n" << kUsage;
    return 2;
  }
  return 0;
}
