#include "sl_evaluation/evaluation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <dirent.h>
#include <stdexcept>

namespace sl_evaluation
{

using sl_decoder::Blob;
using sl_decoder::Decoder;
using sl_decoder::DecoderConfig;
using sl_decoder::DecodeResult;

void EvalStats::add(const EvalStats& o)
{
  frames += o.frames;
  visible += o.visible;
  identified += o.identified;
  decoded += o.decoded;
  valid += o.valid;
  valid_visible += o.valid_visible;
  wrong += o.wrong;
  unverifiable += o.unverifiable;
  near_points += o.near_points;
  sum_abs_error += o.sum_abs_error;
  max_abs_error = std::max(max_abs_error, o.max_abs_error);
  with_depth += o.with_depth;
  abs_errors.insert(abs_errors.end(), o.abs_errors.begin(), o.abs_errors.end());
  decode_seconds.insert(decode_seconds.end(), o.decode_seconds.begin(), o.decode_seconds.end());
}

double EvalStats::decodeMs() const
{
  if (decode_seconds.empty())
    return 0.0;
  std::vector<float> t = decode_seconds;
  const size_t n = t.size() / 2;
  std::nth_element(t.begin(), t.begin() + static_cast<long>(n), t.end());
  double m = t[n];
  if (t.size() % 2 == 0)
    m = 0.5 * (m + *std::max_element(t.begin(), t.begin() + static_cast<long>(n)));
  return 1000.0 * m;
}

double EvalStats::errorPercentileMm(double percent) const
{
  if (!(percent > 0.0 && percent <= 100.0))
    throw std::invalid_argument("errorPercentileMm: percent must be in (0, 100]");
  if (abs_errors.empty())
    return 0.0;
  std::vector<float> sorted = abs_errors;
  const size_t rank = static_cast<size_t>(std::ceil(percent * static_cast<double>(sorted.size()) / 100.0));
  const auto nth = sorted.begin() + static_cast<long>(std::max<size_t>(rank, 1) - 1);
  std::nth_element(sorted.begin(), nth, sorted.end());
  return 1000.0 * static_cast<double>(*nth);
}

namespace
{
/// The primitive whose box (grown by @p margin px) contains projector pixel (x, y), or -1.
int primitiveAt(const sl_projector::Pattern& pattern, float x, float y, double margin)
{
  const sl_projector::PatternConfig& c = pattern.config();
  double px = x, py = y;
  if (c.flip_x)
    px = (c.projector_width - 1) - px;
  if (c.flip_y)
    py = (c.projector_height - 1) - py;
  // Box of (r, col) spans [origin - 0.5, origin + size - 0.5] in pixel-centre coordinates.
  const double fx = (px + 0.5 - c.offset_x - c.gap_x / 2) / c.cellWidth();
  const double fy = (py + 0.5 - c.offset_y - c.gap_y / 2) / c.cellHeight();
  const int col = static_cast<int>(std::floor(fx + margin / c.cellWidth()));
  const int row = static_cast<int>(std::floor(fy + margin / c.cellHeight()));
  if (row < 0 || col < 0 || row >= c.rows || col >= c.cols)
    return -1;
  const cv::Point o = pattern.primitiveOrigin(row, col);
  if (px < o.x - 0.5 - margin || px > o.x + c.primitive_width - 0.5 + margin || py < o.y - 0.5 - margin ||
      py > o.y + c.primitive_height - 0.5 + margin)
    return -1;
  return row * c.cols + col;
}
}  // namespace

EvalStats evaluateFrame(const sl_projector::Pattern& pattern, const sl_sim::RenderOutput& truth,
                        const DecodeResult& result)
{
  EvalStats s;
  s.frames = 1;
  const int cols = pattern.config().cols;
  const int cells = pattern.config().rows * cols;
  std::vector<int> lit(static_cast<size_t>(cells), 0);
  std::vector<float> near(static_cast<size_t>(cells), 1e9f), far(static_cast<size_t>(cells), -1e9f);
  const cv::Mat& pc = truth.projector_coords;
  for (int y = 0; y < pc.rows; ++y)
  {
    const cv::Vec2f* row = pc.ptr<cv::Vec2f>(y);
    const float* depth = truth.depth.ptr<float>(y);
    for (int x = 0; x < pc.cols; ++x)
    {
      if (std::isnan(row[x][0]))
        continue;
      const int p = primitiveAt(pattern, row[x][0], row[x][1], 0.0);
      if (p < 0)
        continue;
      const size_t i = static_cast<size_t>(p);
      ++lit[i];
      near[i] = std::min(near[i], depth[x]);
      far[i] = std::max(far[i], depth[x]);
    }
  }
  std::vector<char> visible(static_cast<size_t>(cells), 0);
  std::vector<int> counts;
  for (int n : lit)
    if (n > 0)
      counts.push_back(n);
  if (!counts.empty())
  {
    std::nth_element(counts.begin(), counts.begin() + static_cast<long>(counts.size() / 2), counts.end());
    const int median = counts[counts.size() / 2];
    // Visible: (nearly) all of the primitive is seen, on one surface (no depth step across it).
    for (size_t i = 0; i < lit.size(); ++i)
    {
      visible[i] = 5 * lit[i] >= 4 * median && far[i] - near[i] <= std::max(0.01f, 0.02f * near[i]);
      s.visible += visible[i];
    }
  }

  s.identified = result.identified;
  s.decoded = result.decoded;
  // Background depth: the far end of the scene in this frame.
  std::vector<float> depths;
  for (const Blob& b : result.blobs)
  {
    if (!b.valid)
      continue;
    const int u = static_cast<int>(std::lround(b.u)), v = static_cast<int>(std::lround(b.v));
    if (u >= 0 && v >= 0 && u < truth.depth.cols && v < truth.depth.rows && std::isfinite(truth.depth.at<float>(v, u)))
      depths.push_back(truth.depth.at<float>(v, u));
  }
  float background = 0.f;
  if (!depths.empty())
  {
    std::sort(depths.begin(), depths.end());
    background = depths[std::min(depths.size() - 1, depths.size() * 9 / 10)];
  }

  for (const Blob& b : result.blobs)
  {
    if (!b.valid)
      continue;
    ++s.valid;
    // Correspondence check around the centroid.
    const int target = b.row * cols + b.col;
    bool lit_near = false, match = false;
    for (int dy = -1; dy <= 1 && !match; ++dy)
      for (int dx = -1; dx <= 1 && !match; ++dx)
      {
        const int u = static_cast<int>(std::lround(b.u + 1.5f * dx)),
                  v = static_cast<int>(std::lround(b.v + 1.5f * dy));
        if (u < 0 || v < 0 || u >= pc.cols || v >= pc.rows)
          continue;
        const cv::Vec2f q = pc.at<cv::Vec2f>(v, u);
        if (std::isnan(q[0]))
          continue;
        lit_near = true;
        match = primitiveAt(pattern, q[0], q[1], 1.0) == target;
      }
    if (!lit_near)
      ++s.unverifiable;
    else if (!match)
      ++s.wrong;
    else if (visible[static_cast<size_t>(target)])
      ++s.valid_visible;

    // Depth error: bilinear ground truth when the four pixels agree, else the nearest pixel.
    const int u0 = static_cast<int>(std::floor(b.u)), v0 = static_cast<int>(std::floor(b.v));
    if (u0 < 0 || v0 < 0 || u0 + 1 >= truth.depth.cols || v0 + 1 >= truth.depth.rows)
      continue;
    const float d00 = truth.depth.at<float>(v0, u0), d10 = truth.depth.at<float>(v0, u0 + 1);
    const float d01 = truth.depth.at<float>(v0 + 1, u0), d11 = truth.depth.at<float>(v0 + 1, u0 + 1);
    float z_true;
    const float lo = std::min(std::min(d00, d10), std::min(d01, d11));
    const float hi = std::max(std::max(d00, d10), std::max(d01, d11));
    if (std::isfinite(lo) && std::isfinite(hi) && hi - lo < 0.005f)
    {
      const float ax = b.u - static_cast<float>(u0), ay = b.v - static_cast<float>(v0);
      z_true = (1 - ay) * ((1 - ax) * d00 + ax * d10) + ay * ((1 - ax) * d01 + ax * d11);
    }
    else
      z_true = truth.depth.at<float>(static_cast<int>(std::lround(b.v)), static_cast<int>(std::lround(b.u)));
    if (!std::isfinite(z_true))
      continue;
    const double error = std::abs(static_cast<double>(b.z) - z_true);
    s.sum_abs_error += error;
    s.max_abs_error = std::max(s.max_abs_error, error);
    s.abs_errors.push_back(static_cast<float>(error));
    ++s.with_depth;
    if (z_true < background - 0.015f)
      ++s.near_points;
  }
  return s;
}

SceneReport evaluateScene(const sl_projector::Rig& rig, const std::string& scene_path, const DecoderConfig& config,
                          int frames, const sl_sim::SimSettings& settings)
{
  return evaluateScene(rig, sl_sim::loadScene(scene_path), sceneStem(scene_path), config, frames, settings);
}

std::string sceneStem(const std::string& path)
{
  const size_t slash = path.find_last_of('/');
  std::string stem = slash == std::string::npos ? path : path.substr(slash + 1);
  if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".yaml") == 0)
    stem.resize(stem.size() - 5);
  return stem;
}

SceneReport evaluateScene(const sl_projector::Rig& rig, const sl_sim::Scene& scene, const std::string& name,
                          const DecoderConfig& config, int frames, const sl_sim::SimSettings& settings, uint64_t seed)
{
  SceneReport report;
  report.scene = name;
  report.model = sl_decoder::depthModeName(config.depth_mode);
  sl_sim::Renderer renderer(rig, settings);
  Decoder decoder(rig, config);
  const cv::Mat pattern = decoder.pattern().render();
  const Eigen::Isometry3d camera = sl_sim::cameraPoseInWorld(rig);
  sl_sim::RenderOutput truth;
  DecodeResult result;
  for (int f = 0; f < frames; ++f)
  {
    renderer.render(scene, pattern, camera, seed + static_cast<uint64_t>(f), truth);
    if (f == 0)
      decoder.decode(truth.image, result);  // warm-up, not timed
    const auto start = std::chrono::steady_clock::now();
    decoder.decode(truth.image, result);
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    EvalStats s = evaluateFrame(decoder.pattern(), truth, result);
    s.decode_seconds.push_back(static_cast<float>(took.count()));
    report.stats.add(s);
  }
  return report;
}

const std::vector<double>& nearFarDistances()
{
  static const std::vector<double> d{ 0.35, 0.40, 0.45, 0.55, 0.70, 0.90, 1.20 };
  return d;
}

sl_sim::Scene planeScene(const sl_projector::Rig& rig, double camera_distance, double albedo)
{
  // The camera's offset from platform_edge (the world origin) along x, as the scene files assume.
  const double camera_x = sl_sim::cameraPoseInWorld(rig).translation().x();
  sl_sim::Scene scene;
  scene.name = "plane";
  sl_sim::SceneObject floor;
  floor.name = "floor";
  floor.pose.linear() = Eigen::Matrix3d::Identity();  // normal +z
  floor.material.albedo = 0.35;
  floor.material.texture.type = sl_sim::TextureType::Noise;
  floor.material.texture.scale = 0.05;
  floor.material.texture.contrast = 0.3;
  floor.floor = true;
  sl_sim::SceneObject plane;
  plane.name = "plane";
  // Local z (the normal) towards the robot (-x); local x up, local y = z x x.
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d::UnitZ();
  r.col(2) = -Eigen::Vector3d::UnitX();
  r.col(1) = r.col(2).cross(r.col(0));
  plane.pose.linear() = r;
  plane.pose.translation() = Eigen::Vector3d(camera_x + camera_distance, 0.0, 1.0);
  plane.size = Eigen::Vector3d(2.0, 2.0, 0.0);
  plane.material.albedo = albedo;
  scene.objects = { floor, plane };
  return scene;
}

std::string defaultScenesDir()
{
  return SL_SIM_SCENES_DIR;
}

std::string defaultRigFile()
{
  return std::string(SL_PROJECTOR_CONFIG_DIR) + "/default_rig.yaml";
}

std::string findScene(const std::vector<std::string>& parts)
{
  const std::string dir = defaultScenesDir();
  DIR* d = opendir(dir.c_str());
  if (!d)
    throw std::runtime_error("cannot open the scenes directory " + dir);
  std::string found;
  while (dirent* e = readdir(d))
  {
    const std::string name = e->d_name;
    bool all = name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0 && !parts.empty() &&
               name.rfind(parts[0], 0) == 0;
    for (const std::string& p : parts)
      all = all && name.find(p) != std::string::npos;
    if (all && (found.empty() || name < found))
      found = name;
  }
  closedir(d);
  if (found.empty())
  {
    std::string what;
    for (const std::string& p : parts)
      what += " '" + p + "'";
    throw std::runtime_error("no scene file with" + what + " in its name in " + dir);
  }
  return dir + "/" + found;
}
}  // namespace sl_evaluation
