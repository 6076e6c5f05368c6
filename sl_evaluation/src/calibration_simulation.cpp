#include "sl_evaluation/calibration_simulation.h"

#include <algorithm>
#include <cmath>
#include <dirent.h>
#include <map>

namespace sl_evaluation
{

using sl_calibration::Board;
using sl_calibration::CalibrationError;
using sl_calibration::DistanceReference;
using sl_calibration::PlaneCalibrationOptions;
using sl_calibration::PlaneNormal;
using sl_decoder::Blob;
using sl_decoder::Decoder;
using sl_decoder::DecoderConfig;
using sl_decoder::DecodeResult;
using sl_decoder::DepthMode;

SimScenes findSimScenes(const std::string& dir_in)
{
  const std::string dir = dir_in.empty() ? defaultScenesDir() : dir_in;
  DIR* d = opendir(dir.c_str());
  if (!d)
    throw CalibrationError("cannot open the scenes directory " + dir);
  SimScenes s;
  while (dirent* e = readdir(d))
  {
    const std::string name = e->d_name;
    if (name.size() < 5 || name.compare(name.size() - 5, 5, ".yaml") != 0)
      continue;
    const std::string path = dir + "/" + name;
    if (name == "calib_wall.yaml")
      s.wall = path;
    else if (name.rfind("calib_board_", 0) == 0)
      s.boards.push_back(path);
    else if (name.rfind("calib_plane_", 0) == 0)
      s.planes.push_back(path);
  }
  closedir(d);
  std::sort(s.boards.begin(), s.boards.end());
  std::sort(s.planes.begin(), s.planes.end());
  if (s.wall.empty())
    throw CalibrationError(dir + ": no calib_wall.yaml (the plane calibration's wall)");
  if (s.planes.empty())
    throw CalibrationError(dir + ": no calib_plane_*.yaml (calibration planes with a board)");
  return s;
}

Board boardOfScene(const sl_sim::Scene& scene)
{
  for (const sl_sim::SceneObject& o : scene.objects)
    if (o.type == sl_sim::ObjectType::Plane && o.material.texture.type == sl_sim::TextureType::Checkerboard)
    {
      Board b;
      b.cols = o.material.texture.cols - 1;
      b.rows = o.material.texture.rows - 1;
      b.square = o.material.texture.square;
      return b;
    }
  throw CalibrationError("scene '" + scene.name + "' has no plane with a checkerboard texture");
}

Eigen::Isometry3d platformEdgeForDistance(const sl_projector::Rig& rig, const sl_sim::Scene& wall_scene,
                                          double distance, const PlaneCalibrationOptions& options)
{
  if (options.normal != PlaneNormal::Robot)
    throw CalibrationError("the simulated wall is perpendicular to the robot (plane normal 'robot')");
  const sl_sim::SceneObject* wall = nullptr;
  for (const sl_sim::SceneObject& o : wall_scene.objects)
    if (o.name == "wall" && o.type == sl_sim::ObjectType::Plane)
      wall = &o;
  if (!wall)
    throw CalibrationError("scene '" + wall_scene.name + "' has no plane named 'wall'");
  const Eigen::Vector3d n = wall->pose.linear().col(2);
  if (std::abs(std::abs(n.x()) - 1.0) > 1e-9)
    throw CalibrationError("scene '" + wall_scene.name + "': the wall must be perpendicular to world x");
  const double wall_x = wall->pose.translation().x();
  // Camera reference: the camera centre (mount.xyz in platform_edge) is `distance` in front of the wall.
  const double edge_x =
      options.reference == DistanceReference::Camera ? wall_x - distance - rig.mount.xyz.x() : wall_x - distance;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = edge_x;
  return pose;
}

sl_sim::Scene withoutTextures(const sl_sim::Scene& scene)
{
  sl_sim::Scene s = scene;
  for (sl_sim::SceneObject& o : s.objects)
    o.material.texture.type = sl_sim::TextureType::None;
  return s;
}

CalibrationSimulator::CalibrationSimulator(const sl_projector::Rig& rig, const sl_sim::SimSettings& settings,
                                           double board_ambient)
  : rig_(rig), settings_(settings), board_settings_(settings)
{
  board_settings_.ambient = board_ambient;
  // A real sensor integrates over the pixel: 16 rays on the board's edges keep the rendered corners
  // about 0.1 px rms from the exact ones (4 rays leave errors up to 0.25 px).
  board_settings_.antialias = 16;
  renderer_.reset(new sl_sim::Renderer(rig_, settings_));
  board_renderer_.reset(new sl_sim::Renderer(rig_, board_settings_));
  pattern_ = sl_projector::Pattern(rig_.pattern).render();
  dark_ = cv::Mat::zeros(pattern_.size(), CV_8UC1);
}

CalibrationSimulator::~CalibrationSimulator() = default;

const sl_sim::RenderOutput& CalibrationSimulator::renderPattern(const sl_sim::Scene& scene,
                                                                const Eigen::Isometry3d& platform_edge_in_world,
                                                                uint64_t seed)
{
  renderer_->render(scene, pattern_, sl_sim::cameraPoseInWorld(rig_, platform_edge_in_world), seed, out_);
  return out_;
}

const sl_sim::RenderOutput& CalibrationSimulator::renderBoard(const sl_sim::Scene& scene, uint64_t seed)
{
  board_renderer_->render(scene, dark_, sl_sim::cameraPoseInWorld(rig_), seed, out_);
  return out_;
}

const sl_sim::RenderOutput& CalibrationSimulator::renderWall(const sl_sim::Scene& wall_scene, double distance,
                                                             const PlaneCalibrationOptions& options, uint64_t seed)
{
  return renderPattern(wall_scene, platformEdgeForDistance(rig_, wall_scene, distance, options), seed);
}

DepthAgreement compareDepth(const sl_projector::Rig& a, const sl_projector::Rig& b, const cv::Mat& image)
{
  DecoderConfig config;
  config.depth_mode = DepthMode::Triangulation;
  Decoder da(a, config), db(b, config);
  DecodeResult ra, rb;
  da.decode(image, ra);
  db.decode(image, rb);
  std::map<int, double> za;
  const int cols = a.pattern.cols;
  for (const Blob& blob : ra.blobs)
    if (blob.valid)
      za[blob.row * cols + blob.col] = blob.z;
  DepthAgreement out;
  double sum = 0.0, sum_z = 0.0;
  for (const Blob& blob : rb.blobs)
  {
    if (!blob.valid)
      continue;
    const auto it = za.find(blob.row * cols + blob.col);
    if (it == za.end())
      continue;
    const double d = std::abs(it->second - blob.z);
    sum += d;
    sum_z += blob.z;
    out.max_mm = std::max(out.max_mm, 1000.0 * d);
    ++out.points;
  }
  if (out.points > 0)
  {
    out.mean_mm = 1000.0 * sum / out.points;
    out.mean_z = sum_z / out.points;
  }
  return out;
}

EvalStats evaluateRendered(const sl_projector::Rig& rig, DepthMode mode, const sl_sim::RenderOutput& truth)
{
  DecoderConfig config;
  config.depth_mode = mode;
  Decoder decoder(rig, config);
  DecodeResult result;
  decoder.decode(truth.image, result);
  return evaluateFrame(decoder.pattern(), truth, result);
}

}  // namespace sl_evaluation
