#include "sl_decoder/epipolar_index.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sl_decoder
{

EpipolarIndex::EpipolarIndex(const sl_projector::Rig& rig, const DecoderConfig& config)
{
  const sl_projector::Pattern pattern(rig.pattern);
  const int rows = rig.pattern.rows, cols = rig.pattern.cols;
  const sl_projector::PinholeModel& cam = rig.camera;
  // Sizes in 64 bits and bounded before anything is allocated: a 262144 x 262144 camera
  // overflowed int here and the tables came out too small (a crash, not an error).
  sl_projector::checkedCells(cam.width, cam.height, "camera image");
  const int n = static_cast<int>(sl_projector::checkedCells(cols, rows, "pattern"));

  // Ray table: undistorted normalised coordinates on a coarse grid, interpolated at run time.
  ray_w_ = cam.width / kRayStep + 2;
  ray_h_ = cam.height / kRayStep + 2;
  ray_table_.resize(sl_projector::checkedCells(ray_w_, ray_h_, "camera ray table"));
  for (int j = 0; j < ray_h_; ++j)
    for (int i = 0; i < ray_w_; ++i)
    {
      const Eigen::Vector3d r = cam.ray(Eigen::Vector2d(i * kRayStep, j * kRayStep));
      ray_table_[static_cast<size_t>(j) * static_cast<size_t>(ray_w_) + static_cast<size_t>(i)] =
          Eigen::Vector2d(r.x(), r.y());
    }

  projector_origin_ = rig.projector_pose.translation;
  directions_.resize(static_cast<size_t>(n));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
    {
      const cv::Point2d p = pattern.primitiveCentroid(r, c);
      Eigen::Vector3d origin, dir;
      rig.projectorRay(Eigen::Vector2d(p.x, p.y), origin, dir);
      directions_[static_cast<size_t>(r * cols + c)] = dir;
    }

  // Point of primitive i's ray at camera depth z (camera optical frame).
  auto pointAtDepth = [&](int i, double z, Eigen::Vector3d& point)
  {
    const Eigen::Vector3d& d = directions_[static_cast<size_t>(i)];
    if (std::abs(d.z()) < 1e-9)
      return false;
    const double s = (z - projector_origin_.z()) / d.z();
    if (s <= 0.0)
      return false;
    point = projector_origin_ + s * d;
    return true;
  };

  // Average pattern steps at the nominal depth, from neighbours that are both in view.
  Eigen::Vector2d east = Eigen::Vector2d::Zero(), south = Eigen::Vector2d::Zero();
  int ne = 0, ns = 0;
  std::vector<Eigen::Vector2d> nominal(static_cast<size_t>(n));
  std::vector<bool> in_view(static_cast<size_t>(n), false);
  for (int i = 0; i < n; ++i)
  {
    Eigen::Vector3d p;
    if (pointAtDepth(i, config.nominal_depth, p))
    {
      nominal[static_cast<size_t>(i)] = cam.project(p);
      in_view[static_cast<size_t>(i)] = cam.inImage(nominal[static_cast<size_t>(i)]);
    }
  }
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
    {
      const int i = r * cols + c;
      if (!in_view[static_cast<size_t>(i)])
        continue;
      if (c + 1 < cols && in_view[static_cast<size_t>(i + 1)])
      {
        east += nominal[static_cast<size_t>(i + 1)] - nominal[static_cast<size_t>(i)];
        ++ne;
      }
      if (r + 1 < rows && in_view[static_cast<size_t>(i + cols)])
      {
        south += nominal[static_cast<size_t>(i + cols)] - nominal[static_cast<size_t>(i)];
        ++ns;
      }
    }
  if (ne == 0 || ns == 0)
    throw std::invalid_argument("the pattern is not visible in the camera at nominal_depth " +
                                std::to_string(config.nominal_depth) + " m: check the rig file and nominal_depth");
  step_east_ = east / ne;
  step_south_ = south / ns;

  // Epipolar curves: sample each primitive's ray uniformly in inverse depth (image motion is
  // linear in it) finely enough for sub-block steps, and list the blocks within the tolerance.
  blocks_x_ = (cam.width + (1 << kBlockShift) - 1) >> kBlockShift;
  blocks_y_ = (cam.height + (1 << kBlockShift) - 1) >> kBlockShift;
  const size_t blocks = sl_projector::checkedCells(blocks_x_, blocks_y_, "epipolar block table");
  std::vector<std::vector<int32_t>> lists(blocks);
  std::vector<int32_t> stamp(blocks, -1);
  const double reach = config.epipolar_tolerance + 1.0;
  const double inv_near = 1.0 / config.min_depth, inv_far = 1.0 / config.max_depth;
  // A curve longer than twice the image's perimeter lies mostly outside the image (a strong
  // distortion, a huge focal length): its samples are capped there, or a rig with camera
  // D: [0, 0, 0, 0, 1e8] took minutes to index. Real rigs' curves are a few hundred px.
  const double max_samples = 2.0 * (cam.width + cam.height) / 0.75;
  Eigen::Vector2d dir_sum = Eigen::Vector2d::Zero();
  visible_ = 0;
  for (int i = 0; i < n; ++i)
  {
    Eigen::Vector3d p_near, p_far;
    if (!pointAtDepth(i, config.min_depth, p_near) || !pointAtDepth(i, config.max_depth, p_far))
      continue;
    const Eigen::Vector2d a = cam.project(p_near), b = cam.project(p_far);
    const double length = (a - b).norm();
    const double wanted = std::isfinite(length) ? std::ceil(length / 0.75) + 1.0 : max_samples;
    const int samples = static_cast<int>(std::max(2.0, std::min(wanted, max_samples)));
    bool seen = false;
    for (int k = 0; k < samples; ++k)
    {
      const double inv = inv_near + (inv_far - inv_near) * k / (samples - 1);
      Eigen::Vector3d p;
      if (!pointAtDepth(i, 1.0 / inv, p))
        continue;
      const Eigen::Vector2d q = cam.project(p);
      if (!std::isfinite(q.x()) || q.x() < -reach || q.y() < -reach || q.x() > cam.width + reach ||
          q.y() > cam.height + reach)
        continue;
      seen = true;
      const int bx0 = std::max(0, static_cast<int>(std::floor((q.x() - reach) / (1 << kBlockShift))));
      const int bx1 = std::min(blocks_x_ - 1, static_cast<int>(std::floor((q.x() + reach) / (1 << kBlockShift))));
      const int by0 = std::max(0, static_cast<int>(std::floor((q.y() - reach) / (1 << kBlockShift))));
      const int by1 = std::min(blocks_y_ - 1, static_cast<int>(std::floor((q.y() + reach) / (1 << kBlockShift))));
      for (int by = by0; by <= by1; ++by)
        for (int bx = bx0; bx <= bx1; ++bx)
        {
          const size_t block = static_cast<size_t>(by) * static_cast<size_t>(blocks_x_) + static_cast<size_t>(bx);
          if (stamp[block] != i)
          {
            stamp[block] = i;
            lists[block].push_back(i);
          }
        }
    }
    if (seen)
    {
      ++visible_;
      dir_sum += (b - a).normalized();
    }
  }
  storeBlocks(lists, pattern.array().values());

  // Do epipolar curves run along the pattern's rows or its columns?
  const Eigen::Vector2d e = step_east_.normalized(), s = step_south_.normalized();
  const Eigen::Vector2d d = dir_sum.normalized();
  along_rows_ = std::abs(d.dot(e)) >= std::abs(d.dot(s));
}

void EpipolarIndex::storeBlocks(const std::vector<std::vector<int32_t>>& lists, const std::vector<int>& values)
{
  // One CSR range per (block, value): a blob looks up only the primitives of its own shape.
  const int max_value = values.empty() ? 0 : *std::max_element(values.begin(), values.end());
  shape_slots_ = static_cast<size_t>(std::max(0, max_value)) + 1;
  const size_t ranges = lists.size() * shape_slots_;
  block_start_.assign(ranges + 1, 0);
  for (size_t k = 0; k < lists.size(); ++k)
    for (const int32_t p : lists[k])
      ++block_start_[k * shape_slots_ + static_cast<size_t>(std::max(0, values[static_cast<size_t>(p)])) + 1];
  for (size_t r = 0; r < ranges; ++r)
    block_start_[r + 1] += block_start_[r];
  entries_.resize(static_cast<size_t>(block_start_[ranges]));
  std::vector<int32_t> fill(block_start_.begin(), block_start_.end() - 1);
  for (size_t k = 0; k < lists.size(); ++k)
    for (const int32_t p : lists[k])
      entries_[static_cast<size_t>(
          fill[k * shape_slots_ + static_cast<size_t>(std::max(0, values[static_cast<size_t>(p)]))]++)] = p;
}

}  // namespace sl_decoder
