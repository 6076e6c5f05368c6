#include "sl_decoder/ray_classifier.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sl_decoder
{

namespace
{
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kSampleSpacing = 4.0;  // px between consecutive samples (one light-map block)
constexpr int kMaxSamples = 256;
constexpr int kFloorMargin = 6;            // px: floor pixels this close to the border are not tested
constexpr float kFloorLight = 0.35f;       // floor light: centre line mean above the background, noise floors
constexpr float kStrongFloorLight = 0.5f;  // floor light that needs no walk up to the floor, noise floors
constexpr float kFloorGap = 0.7f;          // the gaps beside the floor light darker by this fraction of it
constexpr int kBorderBlocks = 2;           // light-map blocks at the image border whose light is nobody's own
constexpr float kSupport = 0.03f;          // m: a suspect needs a neighbouring row's decoded or lit end this close
constexpr int kSupportCols = 2;            // ... in a column at most this far from its own
constexpr int kGlowSupportCols = 3;        // columns searched for a surface behind a suspect in the glow zone
constexpr float kOnFloor = 0.95f;  // a decoded point beyond this fraction of its ray's floor depth is on the floor
constexpr float kGlowChainDepth = 0.08f;  // m: a confirmed glow suspect of a neighbouring row this near in depth
constexpr float kNearFloor = 0.9f;        // a walk stopped beyond this fraction of the floor depth reached it

void check(bool ok, const char* field, const std::string& rule)
{
  if (!ok)
    throw std::invalid_argument(std::string(field) + " " + rule);
}

}  // namespace

const char* toString(RayState s)
{
  switch (s)
  {
    case RayState::Decoded:
      return "decoded";
    case RayState::Floor:
      return "floor";
    case RayState::Dark:
      return "dark";
    case RayState::Lit:
      return "lit";
    case RayState::Unseen:
      return "unseen";
  }
  return "?";
}

void RayConfig::validate() const
{
  check(std::isfinite(min_albedo) && min_albedo > 0.0 && min_albedo <= 1.0, "min_albedo", "must be in (0, 1]");
  check(std::isfinite(pattern_contrast_1m) && pattern_contrast_1m > 0.0 && pattern_contrast_1m <= 1e6,
        "pattern_contrast_1m", "must be in (0, 1e6] DN");
  check(std::isfinite(light_fraction) && light_fraction > 0.0 && light_fraction <= 1.0, "light_fraction",
        "must be in (0, 1]");
  check(std::isfinite(noise_floor) && noise_floor > 0.0 && noise_floor < 255.0, "noise_floor",
        "must be in (0, 255) DN");
  check(std::isfinite(max_range) && max_range > 0.0, "max_range", "must be > 0 m");
  check(std::isfinite(glow_max_depth) && glow_max_depth >= 0.0, "glow_max_depth", "must be >= 0 m");
  check(std::isfinite(saturation_level) && saturation_level > 0.0 && saturation_level <= 256.0, "saturation_level",
        "must be in (0, 256] DN");
}

RayClassifier::RayClassifier(const sl_projector::Rig& rig, const DecoderConfig& decoder_config, const RayConfig& config)
  : config_(config)
{
  config_.validate();
  check(config_.max_range > decoder_config.min_depth && config_.max_range <= decoder_config.max_depth, "max_range",
        "must be in (min_depth, max_depth] of the decoder");
  precompute(rig, decoder_config);
}

Eigen::Vector3f RayClassifier::pointAtDepth(int index, double z) const
{
  const Eigen::Vector3f& d = directions_[static_cast<size_t>(index)];
  const float s = (static_cast<float>(z) - origin_.z()) / d.z();
  return origin_ + s * d;
}

int RayClassifier::blockContrast(int u, int v) const
{
  u = std::min(std::max(u, 0), width_ - 1);
  v = std::min(std::max(v, 0), height_ - 1);
  const size_t b = static_cast<size_t>((v >> kShift) * bw_ + (u >> kShift));
  return bmax_[b] - lmin_[b];
}

void RayClassifier::precompute(const sl_projector::Rig& rig, const DecoderConfig& decoder_config)
{
  const sl_projector::Pattern pattern(rig.pattern);
  const sl_projector::PinholeModel& cam = rig.camera;
  duty_ = static_cast<float>(cv::mean(pattern.render())[0] / 255.0);
  rows_ = rig.pattern.rows;
  cols_ = rig.pattern.cols;
  width_ = cam.width;
  height_ = cam.height;
  bw_ = (width_ + (1 << kShift) - 1) >> kShift;
  bh_ = (height_ + (1 << kShift) - 1) >> kShift;
  min_depth_ = static_cast<float>(decoder_config.min_depth);
  origin_ = rig.projectorCentre().cast<float>();
  const int n = rows_ * cols_;
  directions_.resize(static_cast<size_t>(n));
  prims_.assign(static_cast<size_t>(n), Primitive());
  samples_.clear();
  const Eigen::Vector3d o = rig.projectorCentre();
  const double inv_near = 1.0 / decoder_config.min_depth, inv_far = 1.0 / config_.max_range;
  for (int i = 0; i < n; ++i)
  {
    const cv::Point2d c = pattern.primitiveCentroid(i / cols_, i % cols_);
    Eigen::Vector3d origin, d;
    rig.projectorRay(Eigen::Vector2d(c.x, c.y), origin, d);
    directions_[static_cast<size_t>(i)] = d.cast<float>();
    Primitive& p = prims_[static_cast<size_t>(i)];
    p.shape = static_cast<uint8_t>(pattern.array().value(i / cols_, i % cols_));
    p.begin = p.end = static_cast<int32_t>(samples_.size());
    if (d.z() < 1e-6)
      continue;
    auto pixelAt = [&](double z) { return cam.project(o + ((z - o.z()) / d.z()) * d); };
    const Eigen::Vector2d a = pixelAt(decoder_config.min_depth), b = pixelAt(config_.max_range);
    const double length = (a - b).norm();
    // Bounded in double: a curve of 5e13 px (projector D: [0.02, 0, 0, 2, 0]) overflowed int
    // (found by fuzz/decoder_rig_fuzz.cpp).
    const double wanted = std::isfinite(length) ? std::ceil(length / kSampleSpacing) + 1.0 : 2.0;
    const int count = static_cast<int>(std::min<double>(kMaxSamples, std::max(2.0, wanted)));
    int32_t last_block = -1;
    for (int k = 0; k < count; ++k)
    {
      const double z = 1.0 / (inv_near + (inv_far - inv_near) * k / (count - 1));
      const Eigen::Vector2d q = pixelAt(z);
      if (!std::isfinite(q.x()) || !cam.inImage(q))
        break;  // the walk stops at the image border
      const int u = std::min(width_ - 1, std::max(0, static_cast<int>(std::lround(q.x()))));
      const int v = std::min(height_ - 1, std::max(0, static_cast<int>(std::lround(q.y()))));
      const int32_t block = (v >> kShift) * bw_ + (u >> kShift);
      if (block == last_block)
        continue;  // the nearer sample of a block stands for it
      last_block = block;
      samples_.push_back({ block, static_cast<float>(z), static_cast<float>(1.0 / (z * z)) });
    }
    p.end = static_cast<int32_t>(samples_.size());
    precomputeFloor(rig, pattern, i, p);
  }
  const size_t blocks = static_cast<size_t>(bw_ * bh_);
  bmax_.assign(blocks, 0);
  bmin_.assign(blocks, 0);
  lmin_.assign(blocks, 0);
  tmp_.assign(blocks, 0);
  pad_.assign(static_cast<size_t>(bw_ + 2 * kRadius), 255);
  claim_.assign(blocks, kInf);
  shape_.assign(blocks, 0);
  floor_light_.assign(static_cast<size_t>(n), 0.f);
  lit_free_.assign(static_cast<size_t>(n), -1);
  unsupported_.assign(static_cast<size_t>(n), 0);
  near_other_.assign(static_cast<size_t>(n), 0);
  bounds_.reserve(static_cast<size_t>(n) + 16);
}

namespace
{
/// Where the projector ray through projector pixel (x, y) meets the floor (z = 0 of the mount's
/// parent frame): the point in the camera frame; false when it never does.
bool floorHit(const sl_projector::Rig& rig, const sl_projector::RigidTransform& mount, double x, double y,
              Eigen::Vector3d& hit)
{
  Eigen::Vector3d o, d;
  rig.projectorRay(Eigen::Vector2d(x, y), o, d);
  const Eigen::Vector3d op = mount * o, dp = mount.rotation * d;
  if (dp.z() > -1e-9)
    return false;
  hit = o + (-op.z() / dp.z()) * d;
  return hit.z() > 0.0;
}

/// The camera pixel of a floor hit, false when there is none or it is outside [1, w - 2] x [0, h - 1).
bool floorPixel(const sl_projector::Rig& rig, const sl_projector::RigidTransform& mount, double x, double y,
                Eigen::Vector2d& pixel)
{
  Eigen::Vector3d hit;
  if (!floorHit(rig, mount, x, y, hit))
    return false;
  pixel = rig.camera.project(hit);
  return pixel.x() >= 1.0 && pixel.x() < rig.camera.width - 2.0 && pixel.y() >= 0.0 &&
         pixel.y() < rig.camera.height - 1.0;
}
}  // namespace

void RayClassifier::precomputeFloor(const sl_projector::Rig& rig, const sl_projector::Pattern& pattern, int index,
                                    Primitive& p)
{
  const sl_projector::RigidTransform mount = rig.mount.cameraOpticalInParent();
  const cv::Point2d c = pattern.primitiveCentroid(index / cols_, index % cols_);
  Eigen::Vector3d hit;
  if (!floorHit(rig, mount, c.x, c.y, hit))
    return;
  p.limit = static_cast<float>(hit.z());  // the walk stops here even when the floor is out of view
  const Eigen::Vector3d up = mount.rotation.transpose() * Eigen::Vector3d::UnitZ();
  p.floor_gain = static_cast<float>(std::abs(up.dot(directions_[static_cast<size_t>(index)].cast<double>())) /
                                    (hit.z() * hit.z()));
  const Eigen::Vector2d q = rig.camera.project(hit);
  const bool in_view =
      q.x() >= kFloorMargin && q.y() >= kFloorMargin && q.x() < width_ - kFloorMargin && q.y() < height_ - kFloorMargin;
  if (hit.z() < min_depth_ || hit.z() > config_.max_range || !in_view)
    return;
  // The primitive's box rows in the displayed frame (flips applied).
  const sl_projector::PatternConfig& pc = rig.pattern;
  const cv::Point origin = pattern.primitiveOrigin(index / cols_, index % cols_);
  double y0 = origin.y, y1 = origin.y + pc.primitive_height - 1;
  if (pc.flip_y)
  {
    const double t = (pc.projector_height - 1) - y1;
    y1 = (pc.projector_height - 1) - y0;
    y0 = t;
  }
  // Its centre line and the gap lines beside it, top and bottom row; then the footprint.
  Eigen::Vector2d line[3][2];
  const double half_cell = 0.5 * pc.cellWidth(), dx[3] = { 0.0, -half_cell, half_cell };
  for (int l = 0; l < 3; ++l)
    for (int e = 0; e < 2; ++e)
      if (!floorPixel(rig, mount, c.x + dx[l], e ? y1 : y0, line[l][e]))
        return;
  if (line[0][1].y() < line[0][0].y())
    for (auto& l : line)
      std::swap(l[0], l[1]);
  p.v0 = static_cast<int16_t>(std::lround(line[0][0].y()));
  p.v1 = static_cast<int16_t>(std::lround(line[0][1].y()));
  p.cu0 = static_cast<float>(line[0][0].x());
  p.cu1 = static_cast<float>(line[0][1].x());
  p.lu0 = static_cast<float>(line[1][0].x());
  p.lu1 = static_cast<float>(line[1][1].x());
  p.ru0 = static_cast<float>(line[2][0].x());
  p.ru1 = static_cast<float>(line[2][1].x());
  if (precomputeFootprint(rig, mount, c.x, y0, y1, p))
    p.floor_z = static_cast<float>(hit.z());
}

bool RayClassifier::precomputeFootprint(const sl_projector::Rig& rig, const sl_projector::RigidTransform& mount,
                                        double x, double y0, double y1, Primitive& p) const
{
  // The bounding box of the primitive box's corners on the floor, grown by a pixel, in blocks.
  const double hw = 0.5 * rig.pattern.primitive_width;
  double u_min = 1e9, u_max = -1e9, v_min = 1e9, v_max = -1e9;
  for (const double sx : { -hw, hw })
    for (const double y : { y0 - 0.5, y1 + 0.5 })
    {
      Eigen::Vector3d corner;
      if (!floorHit(rig, mount, x + sx, y, corner))
        return false;
      const Eigen::Vector2d q = rig.camera.project(corner);
      u_min = std::min(u_min, q.x());
      u_max = std::max(u_max, q.x());
      v_min = std::min(v_min, q.y());
      v_max = std::max(v_max, q.y());
    }
  auto block = [](double v, int size)
  {
    const long px = std::min(std::max(static_cast<long>(std::floor(v)), 0L), static_cast<long>(size - 1));
    return static_cast<int16_t>(px >> kShift);
  };
  p.bx0 = block(u_min - 1.0, width_);
  p.bx1 = block(u_max + 1.0, width_);
  p.by0 = block(v_min - 1.0, height_);
  p.by1 = block(v_max + 1.0, height_);
  return true;
}

namespace
{
/// Rounded mean of two grey levels (as _mm_avg_epu8 / _mm_avg_epu16).
inline int avg(int a, int b)
{
  return (a + b + 1) >> 1;
}

/// Brightest 2 x 2 bin mean and mean of the 4 x 4 block at column x of four rows (x + 3 clamped).
inline void blockStats(const uint8_t* const r[4], int x, int width, uint8_t& peak, uint8_t& mean)
{
  int bins[2][2];
  for (int half = 0; half < 2; ++half)
  {
    const int x0 = std::min(x + 2 * half, width - 1), x1 = std::min(x + 2 * half + 1, width - 1);
    bins[0][half] = avg(avg(r[0][x0], r[1][x0]), avg(r[0][x1], r[1][x1]));
    bins[1][half] = avg(avg(r[2][x0], r[3][x0]), avg(r[2][x1], r[3][x1]));
  }
  peak = static_cast<uint8_t>(std::max(std::max(bins[0][0], bins[0][1]), std::max(bins[1][0], bins[1][1])));
  mean = static_cast<uint8_t>(avg(avg(bins[0][0], bins[1][0]), avg(bins[0][1], bins[1][1])));
}

/// blockStats() of four blocks (16 columns) at once; the same rounding.
inline void blockStats4(const uint8_t* const r[4], int x, uint8_t* peak, uint8_t* mean)
{
#if defined(__SSE2__)
  auto load = [&](int j) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(r[j] + x)); };
  const __m128i low8 = _mm_set1_epi16(0x00FF), low16 = _mm_set1_epi32(0x0000FFFF);
  const __m128i a = _mm_avg_epu8(load(0), load(1)), b = _mm_avg_epu8(load(2), load(3));
  const __m128i top = _mm_avg_epu16(_mm_and_si128(a, low8), _mm_srli_epi16(a, 8));
  const __m128i bottom = _mm_avg_epu16(_mm_and_si128(b, low8), _mm_srli_epi16(b, 8));
  const __m128i mx = _mm_max_epi16(top, bottom), mn = _mm_avg_epu16(top, bottom);
  const __m128i bmax = _mm_max_epi16(_mm_and_si128(mx, low16), _mm_srli_epi32(mx, 16));
  const __m128i bmean = _mm_avg_epu16(_mm_and_si128(mn, low16), _mm_srli_epi32(mn, 16));
  const __m128i packed = _mm_packus_epi16(_mm_packs_epi32(bmax, bmean), _mm_setzero_si128());
  uint8_t bytes[16];
  _mm_storeu_si128(reinterpret_cast<__m128i*>(bytes), packed);
  std::copy(bytes, bytes + 4, peak);
  std::copy(bytes + 4, bytes + 8, mean);
#else
  for (int k = 0; k < 4; ++k)
    blockStats(r, x + 4 * k, x + 16, peak[k], mean[k]);
#endif
}

/// out[i] = min(in[i - 2 .. i + 2]) of a row padded with two 255 on each side.
void min5(const uint8_t* __restrict padded, uint8_t* __restrict out, int n)
{
  for (int i = 0; i < n; ++i)
    out[i] =
        std::min(std::min(std::min(padded[i], padded[i + 1]), std::min(padded[i + 3], padded[i + 4])), padded[i + 2]);
}

/// out[i] = min(out[i], in[i]).
void minInto(uint8_t* __restrict out, const uint8_t* __restrict in, int n)
{
  for (int i = 0; i < n; ++i)
    out[i] = std::min(out[i], in[i]);
}
}  // namespace

void RayClassifier::buildLightMap(const cv::Mat& image)
{
  static_assert(kShift == 2 && kRadius == 2, "the light map's kernels are written for 4 px blocks and 5 x 5 blocks");
  // Per block: the brightest of its four 2 x 2 bin means (the peak, with half the pixel noise) and
  // its mean (for the background, with a quarter of it).
  for (int by = 0; by < bh_; ++by)
  {
    const uint8_t* r[4];
    for (int j = 0; j < 4; ++j)
      r[j] = image.ptr<uint8_t>(std::min(height_ - 1, (by << kShift) + j));
    uint8_t* peak = bmax_.data() + by * bw_;
    uint8_t* mean = bmin_.data() + by * bw_;
    int bx = 0;
    for (; (bx << kShift) + 16 <= width_; bx += 4)
      blockStats4(r, bx << kShift, peak + bx, mean + bx);
    for (; bx < bw_; ++bx)
      blockStats(r, bx << kShift, width_, peak[bx], mean[bx]);
  }
  // The local background: the smallest block mean of the 5 x 5 blocks around (separable).
  uint8_t* padded = pad_.data();
  for (int by = 0; by < bh_; ++by)
  {
    std::copy(bmin_.data() + by * bw_, bmin_.data() + (by + 1) * bw_, padded + kRadius);
    min5(padded, tmp_.data() + by * bw_, bw_);
  }
  const int bw = bw_, bh = bh_;  // locals: byte stores could alias the members
  for (int by = 0; by < bh; ++by)
  {
    const int y0 = std::max(0, by - kRadius), y1 = std::min(bh - 1, by + kRadius);
    uint8_t* out = lmin_.data() + by * bw;
    std::copy(tmp_.data() + y0 * bw, tmp_.data() + (y0 + 1) * bw, out);
    for (int y = y0 + 1; y <= y1; ++y)
      minInto(out, tmp_.data() + y * bw, bw);
  }
  // The frame's dark level: the 2nd percentile of the block means (every fourth block).
  int histogram[256] = { 0 };
  for (size_t k = 0; k < bmin_.size(); k += 4)
    ++histogram[bmin_[k]];
  const int target = static_cast<int>(bmin_.size() / 4 / 50);
  int sum = 0, level = 0;
  while (level < 255 && sum + histogram[level] <= target)
    sum += histogram[level++];
  dark_level_ = level;
}

void RayClassifier::buildClaims(const DecodeResult& result)
{
  std::fill(claim_.begin(), claim_.end(), kInf);
  std::fill(shape_.begin(), shape_.end(), static_cast<uint8_t>(0));
  for (const Blob& b : result.blobs)
  {
    if (!b.valid && b.shape == 0)
      continue;
    const int bx0 = std::max(0, (b.x0 - 1) >> kShift), bx1 = std::min(bw_ - 1, b.x1 >> kShift);
    const int by0 = std::max(0, (b.y0 - 1) >> kShift), by1 = std::min(bh_ - 1, b.y1 >> kShift);
    for (int by = by0; by <= by1; ++by)
      for (int bx = bx0; bx <= bx1; ++bx)
      {
        const size_t k = static_cast<size_t>(by * bw_ + bx);
        if (b.valid)
          claim_[k] = std::min(claim_[k], b.z);
        else if (b.level > 0)
          shape_[k] = 255;  // split out of a blurred, overexposed row: its shape is no proof of anything
        else
          shape_[k] = (shape_[k] == 0 || shape_[k] == b.shape) ? static_cast<uint8_t>(b.shape) : uint8_t(255);
      }
  }
}

void RayClassifier::estimateC1(const DecodeResult& result)
{
  bounds_.clear();
  for (const Blob& b : result.blobs)
  {
    if (!b.valid)
      continue;
    // The brightest block well inside the box (its own light), above the background at its centre.
    const int bx0 = std::max(0, (b.x0 + 2) >> kShift), bx1 = std::min(bw_ - 1, (b.x1 - 3) >> kShift);
    const int by0 = std::max(0, (b.y0 + 2) >> kShift), by1 = std::min(bh_ - 1, (b.y1 - 3) >> kShift);
    int peak = 0;
    for (int by = by0; by <= by1; ++by)
      for (int bx = bx0; bx <= bx1; ++bx)
        peak = std::max(peak, static_cast<int>(bmax_[static_cast<size_t>(by * bw_ + bx)]));
    const int cu = std::min(std::max(static_cast<int>(b.u + 0.5f), 0), width_ - 1);
    const int cv = std::min(std::max(static_cast<int>(b.v + 0.5f), 0), height_ - 1);
    const int background = lmin_[static_cast<size_t>((cv >> kShift) * bw_ + (cu >> kShift))];
    if (peak >= config_.saturation_level)
      continue;  // clipped: says nothing about C1
    bounds_.push_back(static_cast<float>(peak - background) * b.z * b.z);
  }
  frame_bound_ = 0.0;
  if (!bounds_.empty())
  {
    const size_t k = (bounds_.size() * 9) / 10;
    std::nth_element(bounds_.begin(), bounds_.begin() + static_cast<long>(k), bounds_.end());
    frame_bound_ = bounds_[k];
  }
  c1_ = std::max(config_.pattern_contrast_1m, frame_bound_);
  k_ = static_cast<float>(config_.light_fraction * config_.min_albedo * c1_);
  inv_z2_min_ = static_cast<float>(config_.noise_floor) / k_;
  detectable_depth_ = std::sqrt(k_ / config_.noise_floor);
}

void RayClassifier::floorProfile(const cv::Mat& image, const Primitive& p, float& centre, float& left,
                                 float& right) const
{
  // The primitive is sheared on the floor: follow its (slanted) centre line and gap lines.
  float sc = 0.f, sl = 0.f, sr = 0.f;
  const int rows = p.v1 - p.v0 + 1;
  const float step = rows > 1 ? 1.f / static_cast<float>(rows - 1) : 0.f;
  for (int j = 0; j < rows; ++j)
  {
    const float t = static_cast<float>(j) * step;
    const uint8_t* row = image.ptr<uint8_t>(p.v0 + j);
    const int uc = static_cast<int>(p.cu0 + t * (p.cu1 - p.cu0) + 0.5f);
    const int ul = static_cast<int>(p.lu0 + t * (p.lu1 - p.lu0) + 0.5f);
    const int ur = static_cast<int>(p.ru0 + t * (p.ru1 - p.ru0) + 0.5f);
    sc += static_cast<float>(row[uc - 1] + row[uc] + row[uc + 1]);
    sl += static_cast<float>(row[ul]);
    sr += static_cast<float>(row[ur]);
  }
  centre = sc / static_cast<float>(3 * rows);
  left = sl / static_cast<float>(rows);
  right = sr / static_cast<float>(rows);
}

float RayClassifier::floorLight(const cv::Mat& image, const Primitive& p) const
{
  const int uc = static_cast<int>(0.5f * (p.cu0 + p.cu1) + 0.5f), vc = (p.v0 + p.v1) / 2;
  const size_t b = static_cast<size_t>((vc >> kShift) * bw_ + (uc >> kShift));
  if (claim_[b] < kInf)
    return 0.f;  // a decoded primitive's light
  // No shape veto here: sheared on the floor, primitives are not identified reliably.
  float centre, left, right;
  floorProfile(image, p, centre, left, right);
  const float light = centre - static_cast<float>(lmin_[b]);
  // Enough light, dark gaps beside it, and no more than a white floor could return there (grazing
  // incidence: far floor hits are too dim to be seen, and brighter light there is someone else's).
  const float noise = static_cast<float>(config_.noise_floor);
  if (light >= kFloorLight * noise && light <= static_cast<float>(c1_) * p.floor_gain &&
      centre - std::max(left, right) >= kFloorGap * light)
    return light;
  return 0.f;
}

void RayClassifier::claimFloor(const Primitive& p)
{
  for (int by = p.by0; by <= p.by1; ++by)
    for (int bx = p.bx0; bx <= p.bx1; ++bx)
    {
      float& c = claim_[static_cast<size_t>(by * bw_ + bx)];
      c = std::min(c, p.floor_z);
    }
}

int RayClassifier::walkSegment(const Primitive& p, int& last_free_out, int& stop) const
{
  // Locals: the byte maps could alias the members for the compiler.
  const Sample* samples = samples_.data();
  const float* claims = claim_.data();
  const uint8_t* shapes = shape_.data();
  const uint8_t* peaks = bmax_.data();
  const uint8_t* backgrounds = lmin_.data();
  const uint8_t* means = bmin_.data();
  const float k_glow = k_ * duty_;
  const float noise = static_cast<float>(config_.noise_floor), k_contrast = k_, inv_z2_min = inv_z2_min_;
  const float glow_depth = static_cast<float>(config_.glow_max_depth), limit = p.limit;
  const int saturated = static_cast<int>(std::ceil(config_.saturation_level)), dark = dark_level_;
  const int bw = bw_, bh = bh_;
  int last_free = -1;  // a local: stores through the reference would not stay in a register
  for (int32_t k = p.begin; k < p.end; ++k)
  {
    const Sample& s = samples[k];
    if (s.z > limit)
    {
      stop = kReachedFloor;  // a ray does not go through the floor
      last_free_out = last_free;
      return k;
    }
    if (s.inv_z2 < inv_z2_min)
    {
      stop = kUndetectable;  // a min_albedo surface would not be seen from here on
      last_free_out = last_free;
      return k;
    }
    const float claim = claims[s.block];
    if (claim < kInf)
    {
      if (claim <= s.z)
      {
        stop = kHidden;
        last_free_out = last_free;
        return k;
      }
      last_free = k;  // explained light of a farther surface: the camera sees through here
      continue;
    }
    // Light: contrast above the local background; near, where defocus smears the pattern, also the
    // brightness above the frame's dark level; saturation always.
    const int peak = peaks[s.block];
    const float light = static_cast<float>(peak - backgrounds[s.block]);
    bool glow = false;
    if (s.z < glow_depth)
    {
      const float expected = std::max(2.f * noise, k_glow * s.inv_z2);
      const int mean = means[s.block], gaps = backgrounds[s.block];
      glow = static_cast<float>(mean - dark) >= expected &&
             static_cast<float>(std::max(gaps - dark, mean - gaps)) >= expected;
    }
    if (peak >= saturated || glow || light >= std::max(noise, k_contrast * s.inv_z2))
    {
      // Someone else's light: a blob identified as another shape, or light at the image border,
      // where blobs are cut and cannot be identified (the pattern is wider than the view).
      const uint8_t shape = shapes[s.block];
      const int bx = s.block % bw, by = s.block / bw;
      const bool border =
          bx < kBorderBlocks || by < kBorderBlocks || bx >= bw - kBorderBlocks || by >= bh - kBorderBlocks;
      stop = border || (shape != 0 && shape != 255 && shape != p.shape) ? kOther : kLit;
      last_free_out = last_free;
      return k;
    }
    last_free = k;
  }
  // The image border or max_range; at the floor if the last sample was (within a sample) there.
  stop = last_free >= 0 && last_free + 1 == p.end && samples[last_free].z >= 0.97f * limit ? kReachedFloor : kEnd;
  last_free_out = last_free;
  return p.end;
}

void RayClassifier::walk(int index, RayOutcome& out)
{
  const Primitive& p = prims_[static_cast<size_t>(index)];
  int last_free = -1, stop = kEnd;
  const int k = walkSegment(p, last_free, stop);
  // Floor: its light is at the floor pixel and the walk checked the segment up to the floor (or was
  // stopped just before it, by the neighbours' floor light); beyond the detectable depth, or where
  // the segment is out of view, clear floor light suffices. A walk stopped earlier by a nearer
  // surface, other light or its own possible light cannot vouch for the floor.
  const float floor_light = floor_light_[static_cast<size_t>(index)];
  const float strong = kStrongFloorLight * static_cast<float>(config_.noise_floor);
  const bool near_floor = k < p.end && samples_[static_cast<size_t>(k)].z >= kNearFloor * p.limit;
  const bool checked = stop == kReachedFloor || ((stop == kHidden || stop == kOther) && near_floor);
  const bool floor =
      floor_light > 0.f && (checked || ((stop == kUndetectable || stop == kEnd) && floor_light >= strong));
  const bool near_other = stop == kOther && samples_[static_cast<size_t>(k)].z < config_.glow_max_depth;
  if (stop == kLit)
  {
    setOutcome(out, RayState::Lit, index, samples_[static_cast<size_t>(k)].z);
    lit_free_[static_cast<size_t>(index)] = last_free;
  }
  else if (floor)
  {
    setOutcome(out, RayState::Floor, index, p.floor_z);
    out.start = origin_;
  }
  else if (near_other)
  {
    // In the glow zone defocus blurs shapes and smears light to the border: the light may be this
    // ray's own. A suspect only if dropUnsupportedSuspects() finds a surface decoded behind it.
    setOutcome(out, RayState::Lit, index, samples_[static_cast<size_t>(k)].z);
    lit_free_[static_cast<size_t>(index)] = last_free;
    near_other_[static_cast<size_t>(index)] = 1;
  }
  else if (last_free >= 0)
  {
    setOutcome(out, RayState::Dark, index, samples_[static_cast<size_t>(last_free)].z);
  }
  // else unseen: nothing was checked (the defaults of RayOutcome)
}

void RayClassifier::setOutcome(RayOutcome& out, RayState state, int index, float z) const
{
  out.state = state;
  out.depth = z;
  out.start = pointAtDepth(index, min_depth_);
  out.end = pointAtDepth(index, z);
}

void RayClassifier::classify(const cv::Mat& image, const DecodeResult& result, std::vector<RayOutcome>& outcomes)
{
  if (image.type() != CV_8UC1 || image.cols != width_ || image.rows != height_)
    throw std::invalid_argument("RayClassifier: expected a CV_8UC1 image of " + std::to_string(width_) + " x " +
                                std::to_string(height_));
  const int n = rows_ * cols_;
  outcomes.assign(static_cast<size_t>(n), RayOutcome());
  buildLightMap(image);
  buildClaims(result);
  estimateC1(result);
  counts_.fill(0);
  for (size_t i = 0; i < result.blobs.size(); ++i)
  {
    const Blob& b = result.blobs[i];
    if (!b.valid || b.row < 0 || b.row >= rows_ || b.col < 0 || b.col >= cols_)
      continue;
    RayOutcome& o = outcomes[static_cast<size_t>(b.row * cols_ + b.col)];
    o.state = RayState::Decoded;
    o.blob = static_cast<int>(i);
    o.depth = b.z;
    o.start = origin_;
    o.end = Eigen::Vector3f(b.x, b.y, b.z);
  }
  // Floor candidates first: their light explains what other segments cross.
  for (int i = 0; i < n; ++i)
  {
    const Primitive& p = prims_[static_cast<size_t>(i)];
    const bool candidate = outcomes[static_cast<size_t>(i)].state != RayState::Decoded && std::isfinite(p.floor_z);
    floor_light_[static_cast<size_t>(i)] = candidate ? floorLight(image, p) : 0.f;
  }
  for (int i = 0; i < n; ++i)  // after all tests: a floor footprint must not veto its neighbour's
    if (floor_light_[static_cast<size_t>(i)] > 0.f)
      claimFloor(prims_[static_cast<size_t>(i)]);
  confirmFloors(result, outcomes);
  for (int i = 0; i < n; ++i)
  {
    RayOutcome& o = outcomes[static_cast<size_t>(i)];
    lit_free_[static_cast<size_t>(i)] = -1;
    near_other_[static_cast<size_t>(i)] = 0;
    if (o.state != RayState::Decoded && o.state != RayState::Floor)
    {
      o = RayOutcome();
      walk(i, o);
    }
  }
  dropUnsupportedSuspects(outcomes);
  for (const RayOutcome& o : outcomes)
    ++counts_[static_cast<size_t>(o.state)];
}

bool RayClassifier::confirmed(const std::vector<RayOutcome>& outcomes, int i) const
{
  const RayOutcome& o = outcomes[static_cast<size_t>(i)];
  // Its own light: a neighbouring row's decoded or lit end within kSupport. A glow-zone suspect at
  // other light is no evidence for anyone else's (nor confirmed this way itself).
  if (near_other_[static_cast<size_t>(i)] == 0 &&
      anyInNeighbourRows(i, kSupportCols,
                         [&](size_t j)
                         {
                           const RayOutcome& q = outcomes[j];
                           return (q.state == RayState::Decoded || (q.state == RayState::Lit && near_other_[j] == 0)) &&
                                  (q.end - o.end).squaredNorm() <= kSupport * kSupport;
                         }))
    return true;
  // Near the camera (glow_max_depth) defocus smears a surface's pattern into a glow that the walk
  // meets before the surface itself (and blurs shapes, so light of another shape may be its own):
  // a surface decoded just behind, in the glow zone, confirms it. Not a floor point: the floor near
  // the robot glows too, in front of no obstacle.
  const float glow_depth = static_cast<float>(config_.glow_max_depth);
  if (!(o.depth < glow_depth))
    return false;
  return anyInNeighbourRows(i, kGlowSupportCols,
                            [&](size_t j)
                            {
                              const RayOutcome& q = outcomes[j];
                              return q.state == RayState::Decoded && q.depth >= o.depth - kSupport &&
                                     q.depth <= glow_depth && q.depth < kOnFloor * prims_[j].limit;
                            });
}

void RayClassifier::dropUnsupportedSuspects(std::vector<RayOutcome>& outcomes)
{
  // A surface returns the pattern of several rows. Unexplained light that ends a ray as a suspect
  // (the pattern's edge cut by the image border, the dim rows stretched on the floor at the foot
  // of a wall) is another primitive's light as often as not, and crosses the segments of one
  // pattern row at a different depth for each column: a suspect that nothing confirms
  // (confirmed()) ends the free part there instead.
  for (int i = 0; i < rows_ * cols_; ++i)
    unsupported_[static_cast<size_t>(i)] =
        outcomes[static_cast<size_t>(i)].state == RayState::Lit && !confirmed(outcomes, i);
  // In the glow zone, where few primitives decode, a confirmed suspect of a neighbouring row at
  // about the same depth also confirms one (one step: unconfirmed suspects never confirm each other).
  const float glow_depth = static_cast<float>(config_.glow_max_depth);
  for (int i = 0; i < rows_ * cols_; ++i)
  {
    const RayOutcome& o = outcomes[static_cast<size_t>(i)];
    if (!unsupported_[static_cast<size_t>(i)] || !(o.depth < glow_depth))
      continue;
    const bool chained = anyInNeighbourRows(i, kSupportCols,
                                            [&](size_t j)
                                            {
                                              return outcomes[j].state == RayState::Lit && unsupported_[j] == 0 &&
                                                     near_other_[j] == 0 &&
                                                     std::fabs(outcomes[j].depth - o.depth) <= kGlowChainDepth;
                                            });
    if (chained)
      unsupported_[static_cast<size_t>(i)] = 2;  // confirmed in this pass; not a source for others
  }
  for (int i = 0; i < rows_ * cols_; ++i)
  {
    if (unsupported_[static_cast<size_t>(i)] != 1)
      continue;
    RayOutcome& o = outcomes[static_cast<size_t>(i)];
    const int32_t last_free = lit_free_[static_cast<size_t>(i)];
    o = RayOutcome();
    if (last_free >= 0)
      setOutcome(o, RayState::Dark, i, samples_[static_cast<size_t>(last_free)].z);
  }
}

void RayClassifier::confirmFloors(const DecodeResult& result, std::vector<RayOutcome>& outcomes)
{
  // Walk the floor candidates first. A candidate that is not confirmed (something nearer may hold
  // its light) must not explain light for the others: then the claims are rebuilt without it.
  bool rejected = false;
  const int n = rows_ * cols_;
  for (int i = 0; i < n; ++i)
  {
    float& light = floor_light_[static_cast<size_t>(i)];
    if (light <= 0.f)
      continue;
    RayOutcome& o = outcomes[static_cast<size_t>(i)];
    walk(i, o);
    if (o.state != RayState::Floor)
    {
      light = 0.f;
      rejected = true;
    }
  }
  if (!rejected)
    return;
  buildClaims(result);
  for (int i = 0; i < n; ++i)
    if (outcomes[static_cast<size_t>(i)].state == RayState::Floor)
      claimFloor(prims_[static_cast<size_t>(i)]);
}

}  // namespace sl_decoder
