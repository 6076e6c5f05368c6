// sl_render: renders one simulated camera image of a scene, no ROS master needed.
//   sl_render --rig RIG.yaml --scene SCENE.yaml --out IMAGE.png [--pattern PATTERN.png]
//             [--depth-out DEPTH.tiff] [--coords-out COORDS.tiff] [--seed N] [--ambient X]
//             [--pose X,Y,YAW] [--set NAME=VALUE ...] [--list-settings]
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sl_sim/renderer.h"
#include "sl_sim/scene.h"
#include "sl_sim/sim_settings.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"
#include "sl_rig/tool_args.h"

namespace
{
const char* kUsage =
    "usage: sl_render --rig RIG.yaml --scene SCENE.yaml --out IMAGE.png [options]\n"
    "Renders what the rig's camera sees of the scene lit by the rig's projector.\n"
    "  --rig FILE          rig (calibration) file, e.g. sl_projector/config/default_rig.yaml\n"
    "  --scene FILE        scene file (see the sl_sim README)\n"
    "  --out FILE          the camera image (8-bit grey PNG, or any format OpenCV writes)\n"
    "  --pattern FILE      the projector frame (grey image of the projector's size); default: the\n"
    "                      rig's own pattern\n"
    "  --depth-out FILE    ground-truth depth, 32-bit float TIFF (camera z, m; NaN: nothing)\n"
    "  --coords-out FILE   projector pixel per camera pixel, 3-channel 32-bit float TIFF (x, y, 0; NaN: unlit)\n"
    "  --seed N            noise seed (default 0); the same seed gives the same image\n"
    "  --ambient X         ambient light (same as --set ambient=X)\n"
    "  --pose X,Y,YAW      pose of the robot's platform_edge frame in the world, m and rad (default 0,0,0)\n"
    "  --set NAME=VALUE    any simulator setting (repeatable); --list-settings shows them\n"
    "  --list-settings     print every setting with its default and exit\n";

int usageError(const std::string& message)
{
  std::cerr << "sl_render: " << message << "\n" << kUsage;
  return 2;
}

bool parseNumber(const std::string& text, double& value)
{
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && end && *end == '\0';
}

/// --pose X,Y,YAW.
Eigen::Vector3d parsePose(const std::string& v)
{
  const std::invalid_argument refusal("--pose needs three numbers X,Y,YAW, got '" + v + "'");
  std::stringstream ss(v);
  std::string part;
  std::vector<double> p;
  while (std::getline(ss, part, ','))
  {
    double x;
    if (!parseNumber(part, x))
      throw refusal;
    p.push_back(x);
  }
  if (p.size() != 3)
    throw refusal;
  return Eigen::Vector3d(p[0], p[1], p[2]);
}

/// --set NAME=VALUE: a number, or true/false.
void parseSet(const std::string& v, sl_sim::SimSettings& settings)
{
  const size_t eq = v.find('=');
  double x;
  std::string text = eq == std::string::npos ? "" : v.substr(eq + 1);
  if (text == "true")
    text = "1";
  else if (text == "false")
    text = "0";
  if (eq == std::string::npos || !parseNumber(text, x))
    throw std::invalid_argument("--set needs NAME=VALUE with a number (or true/false), got '" + v + "'");
  try
  {
    sl_sim::setSimSetting(settings, v.substr(0, eq), x);
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument(std::string("--set: ") + e.what());
  }
}

void listSettings()
{
  const sl_sim::SimSettings defaults;
  std::cout << std::left << std::setw(26) << "name" << std::setw(12) << "default" << std::setw(14) << "unit"
            << "meaning\n";
  for (const sl_sim::SimSettingInfo& info : sl_sim::simSettingsInfo())
  {
    std::ostringstream value;
    const double v = sl_sim::getSimSetting(defaults, info.name);
    if (info.kind == sl_sim::SimSettingInfo::Kind::Bool)
      value << (v != 0.0 ? "true" : "false");
    else
      value << v;
    std::cout << std::left << std::setw(26) << info.name << std::setw(12) << value.str() << std::setw(14) << info.unit
              << info.description << "\n";
  }
}

/// Writes the 2-channel projector coordinates as a 3-channel float image (x, y, 0): image writers
/// take 1, 3 or 4 channels, not 2.
bool writeCoords(const std::string& path, const cv::Mat& coords)
{
  std::vector<cv::Mat> channels;
  cv::split(coords, channels);
  channels.push_back(cv::Mat::zeros(coords.size(), CV_32F));
  cv::Mat out;
  cv::merge(channels, out);
  return cv::imwrite(path, out);
}
}  // namespace

int main(int argc, char** argv)
{
  std::string rig_path, scene_path, out_path, pattern_path, depth_path, coords_path;
  uint64_t seed = 0;
  sl_sim::SimSettings settings;
  Eigen::Vector3d pose(0.0, 0.0, 0.0);
  try
  {
    sl_rig::ToolArgs args(argc, argv);
    for (std::string a; args.next(a);)
    {
      if (a == "--help" || a == "-h")
      {
        std::cout << kUsage;
        return 0;
      }
      else if (a == "--list-settings")
      {
        listSettings();
        return 0;
      }
      else if (a == "--rig")
        rig_path = args.value();
      else if (a == "--scene")
        scene_path = args.value();
      else if (a == "--out")
        out_path = args.value();
      else if (a == "--pattern")
        pattern_path = args.value();
      else if (a == "--depth-out")
        depth_path = args.value();
      else if (a == "--coords-out")
        coords_path = args.value();
      else if (a == "--seed")
        seed = static_cast<uint64_t>(args.integer(0));
      else if (a == "--ambient")
        settings.ambient = args.number();
      else if (a == "--pose")
        pose = parsePose(args.value());
      else if (a == "--set")
        parseSet(args.value(), settings);
      else
        args.unknown();
    }
    if (rig_path.empty() || scene_path.empty() || out_path.empty())
      throw std::invalid_argument("--rig, --scene and --out are required");
  }
  catch (const std::invalid_argument& e)
  {
    return usageError(e.what());
  }

  try
  {
    const sl_projector::Rig rig = sl_projector::loadRig(rig_path);
    const sl_sim::Scene scene = sl_sim::loadScene(scene_path);
    cv::Mat pattern;
    if (pattern_path.empty())
      pattern = sl_projector::Pattern(rig.pattern).render();
    else
    {
      pattern = cv::imread(pattern_path, cv::IMREAD_GRAYSCALE);
      if (pattern.empty())
        throw std::runtime_error(pattern_path + ": cannot read the pattern image");
      if (pattern.cols != rig.projector.width || pattern.rows != rig.projector.height)
        throw std::runtime_error(pattern_path + ": the pattern is " + std::to_string(pattern.cols) + " x " +
                                 std::to_string(pattern.rows) + " px, the rig's projector " +
                                 std::to_string(rig.projector.width) + " x " + std::to_string(rig.projector.height));
    }
    try
    {
      settings.validate();
    }
    catch (const std::invalid_argument& e)
    {
      return usageError(std::string("invalid setting: ") + e.what());
    }
    sl_sim::Renderer renderer(rig, settings);
    Eigen::Isometry3d platform_edge = Eigen::Isometry3d::Identity();
    platform_edge.translation() = Eigen::Vector3d(pose.x(), pose.y(), 0.0);
    platform_edge.linear() = Eigen::AngleAxisd(pose.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    sl_sim::RenderOutput out;
    renderer.render(scene, pattern, sl_sim::cameraPoseInWorld(rig, platform_edge), seed, out);
    if (!cv::imwrite(out_path, out.image))
      throw std::runtime_error(out_path + ": cannot write the image");
    if (!depth_path.empty() && !cv::imwrite(depth_path, out.depth))
      throw std::runtime_error(depth_path + ": cannot write the depth image (use .tiff)");
    if (!coords_path.empty() && !writeCoords(coords_path, out.projector_coords))
      throw std::runtime_error(coords_path + ": cannot write the projector coordinates (use .tiff)");
  }
  catch (const std::exception& e)
  {
    std::cerr << "sl_render: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
