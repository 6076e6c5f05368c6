#include "sl_decoder/decoder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "sl_rig/primitives.h"

namespace sl_decoder
{

namespace
{
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point& t)
{
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

// Row and column steps of each direction.
constexpr int kDRow[4] = { -1, 0, 1, 0 };
constexpr int kDCol[4] = { 0, -1, 0, 1 };
constexpr int kOpposite[4] = { kSouth, kEast, kNorth, kWest };

// Confidence factors of blobs split out of merged ones and of cells read from an outline.
constexpr float kSplitWeight = 0.8f;
constexpr float kOutlineWeight = 0.6f;

// A rival candidate within this many pixels of the winner's epipolar error is as plausible.
constexpr float kRivalEpipolarMargin = 0.5f;

int popcount4(uint8_t bits)
{
  return (bits & 1) + ((bits >> 1) & 1) + ((bits >> 2) & 1) + ((bits >> 3) & 1);
}

/// Box sizes below this are counted (sizeMedians()).
constexpr int kCounted = 128;

/// The element at index size / 2 of @p values sorted, from @p counts (per value below kCounted)
/// when @p counted, else by a selection (reorders @p values).
int upperMedian(std::vector<int>& values, const int* counts, bool counted)
{
  const size_t mid = values.size() / 2;
  if (!counted)
  {
    std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
    return values[mid];
  }
  size_t below = 0;
  int v = 0;
  for (; below + static_cast<size_t>(counts[v]) <= mid; ++v)
    below += static_cast<size_t>(counts[v]);
  return v;
}

}  // namespace

Decoder::Decoder(const sl_projector::Rig& rig, const DecoderConfig& config)
  : rig_(rig),
    config_(config),
    pattern_(rig.pattern),
    detector_(config),
    classifier_(config, rig.pattern.primitive_width, rig.pattern.primitive_height)
{
  config_.validate();
  rig_.validate();
  const size_t cells = static_cast<size_t>(rig.pattern.rows) * static_cast<size_t>(rig.pattern.cols);
  if (config_.depth_mode == DepthMode::Rational && rig_.tables.rational.size() != cells)
    throw std::invalid_argument("depth_mode rational needs depth_tables.rational in the calibration file");
  if (config_.depth_mode == DepthMode::Linear && rig_.tables.linear.size() != cells)
    throw std::invalid_argument("depth_mode linear needs depth_tables.linear in the calibration file");
  index_.reset(new EpipolarIndex(rig_, config_));
  try
  {
    words_.reset(new sl_projector::WordTable(pattern_.array()));
  }
  catch (const std::invalid_argument&)
  {
    words_.reset();  // a pattern whose words repeat decodes from candidates and support alone
  }
  owner_.assign(cells, -1);
  preparePrimitives();
  // A primitive's box in the image: its share of the pattern's cell, scaled by the local steps.
  const sl_projector::PatternConfig& pc = rig.pattern;
  // The pattern's rows are tilted in the image by a roll of camera or projector: their slope.
  const double dx = index_->stepEast().x(), slope = std::abs(dx) > 1e-6 ? index_->stepEast().y() / dx : 0.0;
  detector_.setPrimitiveSize(primitiveWidth(), index_->stepSouth().norm() * pc.primitive_height / pc.cellHeight(),
                             std::abs(dx), slope);
  // Shape centroids below the box centre (pattern px) of outline cells: fixed per shape, and
  // rendering a bitmap per cell cost more than the rest of the cell's decoding.
  for (int v = 1; v <= 4; ++v)
    band_cell_offset_[static_cast<size_t>(v)] =
        sl_projector::shapeCentroid(v, pc.primitive_width, pc.primitive_height).y - 0.5 * (pc.primitive_height - 1);
  grid_cell_ = std::max(4.0, 0.75 * std::min(index_->stepEast().norm(), index_->stepSouth().norm()));
  grid_w_ = static_cast<int>(std::ceil(rig.camera.width / grid_cell_)) + 1;
  grid_h_ = static_cast<int>(std::ceil(rig.camera.height / grid_cell_)) + 1;
  grid_cells_ = sl_projector::checkedCells(grid_w_, grid_h_, "neighbour grid");
}

Decoder::~Decoder() = default;

double Decoder::patternBlur(double depth, double defocus_scale) const
{
  constexpr double kBase = 0.3;  // px, either lens at its focus
  // A disc of diameter d has the second moment of a Gaussian of sigma d / 4.
  const double cam = defocus_scale * rig_.camera_optics.defocusDiameter(rig_.camera.fx, depth) / 4.0;
  const double proj = defocus_scale * rig_.projector_optics.defocusDiameter(rig_.projector.fx, depth) / 4.0;
  const double magnification = rig_.camera.fx / rig_.projector.fx;
  return std::sqrt(kBase * kBase + cam * cam + (kBase * kBase + proj * proj) * magnification * magnification);
}

double Decoder::primitiveWidth() const
{
  return index_->stepEast().norm() * rig_.pattern.primitive_width / rig_.pattern.cellWidth();
}

void Decoder::preparePrimitives()
{
  const int rows = rig_.pattern.rows, cols = rig_.pattern.cols;
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  edges_.assign(n, 0);
  dir_dot_origin_.resize(n);
  for (int d = 0; d < 4; ++d)
    adjacent_step_[d] = kDRow[d] * cols + kDCol[d];
  const Eigen::Vector3d& o = index_->projectorOrigin();
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
    {
      const size_t p = static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c);
      for (int d = 0; d < 4; ++d)
      {
        const int rr = r + kDRow[d], cc = c + kDCol[d];
        if (rr >= 0 && cc >= 0 && rr < rows && cc < cols)
          edges_[p] |= static_cast<uint8_t>(1 << d);
      }
      dir_dot_origin_[p] = index_->projectorDirection(static_cast<int>(p)).dot(o);
    }
}

void Decoder::decode(const cv::Mat& image, DecodeResult& result)
{
  if (image.type() != CV_8UC1)
    throw std::invalid_argument("decoder input must be mono8 (CV_8UC1)");
  if (image.cols != rig_.camera.width || image.rows != rig_.camera.height)
    throw std::invalid_argument("image is " + std::to_string(image.cols) + " x " + std::to_string(image.rows) +
                                " but the calibration's camera is " + std::to_string(rig_.camera.width) + " x " +
                                std::to_string(rig_.camera.height));
  Clock::time_point start = Clock::now(), t = start;
  result.identified = result.decoded = result.valid = 0;

  detector_.detectBoxes(image, result.blobs);
  result.times.detect = msSince(t);

  for (Blob& b : result.blobs)
  {
    if (b.level == BlobDetector::kBandLevel)
      placeBandCell(b);
    else
    {
      classifier_.classify(image, b);
      if (b.shape > 0)
        classifier_.refineCentroid(image, b);
    }
    result.identified += b.shape > 0;
  }
  detector_.centroids(result.blobs);  // the blobs that keep the labelling's centroid (u still NaN)
  result.times.classify = msSince(t);

  findCandidates(result);
  result.times.candidates = msSince(t);
  findNeighbours(result);
  result.times.neighbours = msSince(t);
  correspond(result);
  result.times.correspond = msSince(t);
  computeDepth(result);
  result.times.depth = msSince(t);
  result.times.total = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void Decoder::placeBandCell(Blob& b) const
{
  // The detector read the outline as the camera shows it; the pattern may run right to left or
  // bottom to top there (a mirrored or upside-down mounting): 1 W L R, 2 W R L, 3 L R W, 4 R L W.
  static constexpr int kMirrorX[5] = { 0, 2, 1, 4, 3 };
  static constexpr int kMirrorY[5] = { 0, 4, 3, 2, 1 };
  if (index_->stepEast().x() < 0.0)
    b.shape = kMirrorX[b.shape];
  if (index_->stepSouth().y() < 0.0)
    b.shape = kMirrorY[b.shape];
  // From the box centre to the shape's centroid, which is what the decoder locates.
  const sl_projector::PatternConfig& pc = rig_.pattern;
  const double offset = band_cell_offset_[static_cast<size_t>(b.shape)];
  b.v += static_cast<float>(offset * index_->stepSouth().y() / pc.cellHeight());
}

void Decoder::sizeMedians(const std::vector<Blob>& blobs, float* median_w, float* median_h)
{
  // Box sizes are small: counting them as they are listed is cheaper than a selection (the same
  // element: sorted[n / 2]). A level with a size beyond the counts is selected from its list.
  int counts_w[kSizeLevels][kCounted] = {}, counts_h[kSizeLevels][kCounted] = {};
  bool counted[kSizeLevels];
  for (size_t l = 0; l < kSizeLevels; ++l)
  {
    sizes_w_[l].clear();
    sizes_h_[l].clear();
    counted[l] = true;
  }
  for (const Blob& b : blobs)
    if (b.shape > 0)
    {
      const size_t l = levelOf(b);
      const int w = b.width(), h = b.height();
      sizes_w_[l].push_back(w);
      sizes_h_[l].push_back(h);
      const bool in_range = w >= 0 && h >= 0 && w < kCounted && h < kCounted;
      counted[l] = counted[l] && in_range;
      counts_w[l][in_range ? w : 0] += in_range;
      counts_h[l][in_range ? h : 0] += in_range;
    }
  for (size_t l = 0; l < kSizeLevels; ++l)
  {
    median_w[l] = median_h[l] = 0.f;
    if (sizes_w_[l].empty())
      continue;
    median_w[l] = static_cast<float>(upperMedian(sizes_w_[l], counts_w[l], counted[l]));
    median_h[l] = static_cast<float>(upperMedian(sizes_h_[l], counts_h[l], counted[l]));
  }
}

float Decoder::borderCut(const Blob& b, float typical_w, float typical_h) const
{
  // A blob at the image's border that is smaller across it than the typical blob is cut by it: its
  // centroid lies off by up to half the missing part.
  float cut = 0.f;
  if (b.x0 <= 0 || b.x1 >= rig_.camera.width)
    cut = std::max(cut, 0.5f * (typical_w - static_cast<float>(b.width())));
  if (b.y0 <= 0 || b.y1 >= rig_.camera.height)
    cut = std::max(cut, 0.5f * (typical_h - static_cast<float>(b.height())));
  return cut;
}

void Decoder::findCandidates(DecodeResult& result)
{
  const std::vector<Blob>& blobs = result.blobs;
  cand_begin_.resize(blobs.size() + 1);
  rays_.resize(blobs.size());
  units_.resize(blobs.size());
  typical_.resize(blobs.size());
  cut_.resize(blobs.size());
  ranges_.resize(blobs.size());
  // A primitive cut by an occlusion or the floor, or merged with a neighbour, has an odd size and
  // a biased centroid: it gets no candidates (it can still be seen as a neighbour).
  // Blobs split out of merged components were cut at a raised threshold: each level has its own
  // typical size.
  float median_w[kSizeLevels], median_h[kSizeLevels];
  sizeMedians(blobs, median_w, median_h);
  const float dev = static_cast<float>(config_.max_size_deviation);
  // First every blob's camera ray, then the candidates: a ray's interpolation and normalisation
  // ahead of each blob's candidates made one long dependent chain per blob.
  for (size_t bi = 0; bi < blobs.size(); ++bi)
  {
    const Blob& b = blobs[bi];
    // One pixel of slack: boxes are whole pixels.
    const float mw = median_w[levelOf(b)], mh = median_h[levelOf(b)];
    typical_[bi] = b.shape != 0 && !(std::abs(static_cast<float>(b.width()) - mw) > dev * mw + 1.f ||
                                     std::abs(static_cast<float>(b.height()) - mh) > dev * mh + 1.f);
    cut_[bi] = typical_[bi] ? borderCut(b, mw, mh) : 0.f;
    if (!typical_[bi])
      continue;
    rays_[bi] = index_->cameraRay(b.u, b.v);
    units_[bi] = rays_[bi].normalized();
    // The look-ups in the block table, ahead of their use (their cache misses overlap).
    index_->candidates(b.u, b.v, b.shape, ranges_[bi].first, ranges_[bi].second);
  }
  size_t used = 0;  // cands_ is a buffer: its first `used` entries are this frame's
  for (size_t bi = 0; bi < blobs.size(); ++bi)
  {
    cand_begin_[bi] = static_cast<int32_t>(used);
    if (typical_[bi])
      used = appendCandidates(bi, units_[bi], used);
  }
  cand_begin_[blobs.size()] = static_cast<int32_t>(used);
  cands_.resize(used);
}

// Inline (only this file calls it): an exported member is not inlined in a shared library.
inline size_t Decoder::keepCandidate(int32_t p, const RayApproach& r, size_t used)
{
  // Candidates up to twice the tolerance are kept to compete: a centroid biased by texture or
  // a partial occlusion may push the true primitive just outside the tolerance while a wrong
  // one along the same epipolar curve stays inside; such a blob must stay undecided.
  // The slot is written whatever the outcome and kept or not without a branch: the outcome is
  // known only at the end of a long chain of divisions, and a mispredicted branch waited for it.
  const bool rejected = (r.denom < 1e-12) | (r.z < config_.min_depth) | (r.z > config_.max_depth) | (r.u <= 0.0) |
                        (r.epipolar_px > 2.0 * config_.epipolar_tolerance);
  Candidate& k = cands_[used];
  k.primitive = p;
  k.depth = static_cast<float>(r.z);
  k.epipolar = static_cast<float>(r.epipolar_px);
  k.bits = 0;
  k.tight = r.epipolar_px <= config_.epipolar_tolerance;
  k.edges = edges_[static_cast<size_t>(p)];
  cand_z_[used] = r.z;
  return used + !rejected;
}

inline size_t Decoder::appendCandidates(size_t bi, const Eigen::Vector3d& unit, size_t used)
{
  CameraRayTerms cam;
  cam.o = index_->projectorOrigin();
  cam.fx = rig_.camera.fx;
  cam.d1 = unit;
  cam.d1o = cam.d1.dot(cam.o);
  const int32_t *it = ranges_[bi].first, *end = ranges_[bi].second;
  if (cands_.size() < used + static_cast<size_t>(end - it))
  {
    cands_.resize(std::max(cands_.capacity(), used + static_cast<size_t>(end - it)));  // no allocation once warm
    cand_z_.resize(cands_.size());
  }
  // Two primitives at a time (the divisions and square roots are most of the work).
  RayApproach ra, rb;
  for (; end - it >= 2; it += 2)
  {
    rayApproach2(cam, index_->projectorDirection(it[0]), dir_dot_origin_[static_cast<size_t>(it[0])],
                 index_->projectorDirection(it[1]), dir_dot_origin_[static_cast<size_t>(it[1])], ra, rb);
    used = keepCandidate(it[0], ra, used);
    used = keepCandidate(it[1], rb, used);
  }
  if (it != end)
    used = keepCandidate(
        *it, rayApproach(cam, index_->projectorDirection(*it), dir_dot_origin_[static_cast<size_t>(*it)]), used);
  return used;
}

void Decoder::fillGrid(const std::vector<Blob>& blobs)
{
  const size_t cells = grid_cells_;
  grid_start_.assign(cells + 1, 0);
  blob_cell_.resize(blobs.size());
  // Counting sort of identified blobs into grid cells, each with its centroid (a compact copy).
  for (size_t i = 0; i < blobs.size(); ++i)
  {
    const Blob& b = blobs[i];
    if (b.shape == 0)
      continue;
    const int gx = std::min(grid_w_ - 1, std::max(0, static_cast<int>(b.u / grid_cell_)));
    const int gy = std::min(grid_h_ - 1, std::max(0, static_cast<int>(b.v / grid_cell_)));
    blob_cell_[i] = static_cast<size_t>(gy) * static_cast<size_t>(grid_w_) + static_cast<size_t>(gx);
    ++grid_start_[blob_cell_[i] + 1];
  }
  for (size_t k = 0; k < cells; ++k)
    grid_start_[k + 1] += grid_start_[k];
  grid_items_.resize(static_cast<size_t>(grid_start_[cells]));
  grid_fill_.assign(grid_start_.begin(), grid_start_.end() - 1);
  for (size_t i = 0; i < blobs.size(); ++i)
    if (blobs[i].shape > 0)
      grid_items_[static_cast<size_t>(grid_fill_[blob_cell_[i]]++)] =
          GridItem{ blobs[i].u, blobs[i].v, static_cast<int32_t>(i) };
}

void Decoder::neighbourWindows(NeighbourWindow* win) const
{
  const Eigen::Vector2d steps[4] = { -index_->stepSouth(), -index_->stepEast(), index_->stepSouth(),
                                     index_->stepEast() };
  const double across_len[4] = { index_->stepEast().norm(), index_->stepSouth().norm(), index_->stepEast().norm(),
                                 index_->stepSouth().norm() };
  const float amin = static_cast<float>(config_.neighbour_along_min);
  const float amax = static_cast<float>(config_.neighbour_along_max);
  const float cmax = static_cast<float>(config_.neighbour_across);
  for (int d = 0; d < 4; ++d)
  {
    NeighbourWindow& w = win[d];
    w.sx = static_cast<float>(steps[d].x());
    w.sy = static_cast<float>(steps[d].y());
    w.len = static_cast<float>(steps[d].norm());
    w.ax = w.sx / w.len;
    w.ay = w.sy / w.len;
    w.cx = -w.ay;
    w.cy = w.ax;
    w.across = static_cast<float>(across_len[d]);
    w.amin = amin;
    w.amax = amax;
    w.cmax = cmax;
    w.mid = 0.5f * (amin + amax);
    const float ea = 0.5f * (amax - amin) * w.len, ec = cmax * w.across;
    w.hx = std::abs(w.ax) * ea + std::abs(w.cx) * ec;
    w.hy = std::abs(w.ay) * ea + std::abs(w.cy) * ec;
  }
}

void Decoder::findNeighbours(DecodeResult& result)
{
  std::vector<Blob>& blobs = result.blobs;
  fillGrid(blobs);
  NeighbourWindow win[4];
  neighbourWindows(win);
  // Only the south and east windows are searched. The west and north ones follow: the windows of
  // opposite directions are mirror images, so blob n lies in blob i's east window at cost C exactly
  // (bit for bit) when i lies in n's west window at cost C. Each blob found in a searched window is
  // offered to the mirrored one (offered_cost_, offered_key_).
  for (Blob& b : blobs)
    for (int d = 0; d < 4; ++d)
      b.neighbour[d] = -1;
  offered_cost_.assign(2 * blobs.size(), kNoCost);
  offered_key_.resize(2 * blobs.size());
  for (size_t i = 0; i < blobs.size(); ++i)
    if (blobs[i].shape > 0)
      for (const int d : { kSouth, kEast })
        blobs[i].neighbour[d] = searchWindow(blobs, static_cast<int>(i), win[d], kOpposite[d]);
}

inline int Decoder::searchWindow(std::vector<Blob>& blobs, int i, const NeighbourWindow& w, int mirrored)
{
  const Blob& b = blobs[static_cast<size_t>(i)];
  const float inv_cell = static_cast<float>(1.0 / grid_cell_);
  // The grid cells under the window's bounding box.
  const float mx = b.u + w.sx * w.mid, my = b.v + w.sy * w.mid;
  const int gx0 = std::max(0, static_cast<int>((mx - w.hx) * inv_cell));
  const int gx1 = std::min(grid_w_ - 1, static_cast<int>((mx + w.hx) * inv_cell));
  const int gy0 = std::max(0, static_cast<int>((my - w.hy) * inv_cell));
  const int gy1 = std::min(grid_h_ - 1, static_cast<int>((my + w.hy) * inv_cell));
  float best = kNoCost;
  int best_j = -1;
  // The cells gx0..gx1 of a grid row are one run of items (in the order cell by cell).
  for (int gy = gy0; gy <= gy1 && gx0 <= gx1; ++gy)
  {
    const size_t row = static_cast<size_t>(gy) * static_cast<size_t>(grid_w_);
    const int32_t k1 = grid_start_[row + static_cast<size_t>(gx1) + 1];
    for (int32_t k = grid_start_[row + static_cast<size_t>(gx0)]; k < k1; ++k)
    {
      const GridItem& n = grid_items_[static_cast<size_t>(k)];
      const float cost = windowCost(n.u - b.u, n.v - b.v, w);
      // Selected without a branch: whether a blob lies in the window is a coin toss.
      best_j = cost < best ? n.j : best_j;
      best = cost < best ? cost : best;
      if (cost < kNoCost)
        offer(blobs, n.j, mirrored, i, cost);
    }
  }
  return best_j;
}

inline void Decoder::offer(std::vector<Blob>& blobs, int n, int d, int i, float cost)
{
  // Blob n's own search of window d would have scanned cell by cell, then by index: the first of
  // equal costs in that order wins.
  const size_t slot = 2 * static_cast<size_t>(n) + (d == kWest ? 1 : 0);
  const uint64_t key = (static_cast<uint64_t>(blob_cell_[static_cast<size_t>(i)]) << 32) | static_cast<uint32_t>(i);
  if (cost < offered_cost_[slot] || (cost == offered_cost_[slot] && key < offered_key_[slot]))
  {
    offered_cost_[slot] = cost;
    offered_key_[slot] = key;
    blobs[static_cast<size_t>(n)].neighbour[d] = i;
  }
}

void Decoder::correspond(DecodeResult& result)
{
  if (config_.identify_by_words && words_)
  {
    correspondByWords(result);
    return;
  }
  const std::vector<Blob>& blobs = result.blobs;
  // Discriminating directions lie along the epipolar curves; the others confirm the shape.
  const uint8_t discriminating = index_->epipolarAlongRows() ? static_cast<uint8_t>((1 << kWest) | (1 << kEast))
                                                             : static_cast<uint8_t>((1 << kNorth) | (1 << kSouth));
  const uint8_t confirming = static_cast<uint8_t>(0xF & ~discriminating);
  countSupport(blobs);
  label_.assign(blobs.size(), -1);
  for (size_t i = 0; i < blobs.size(); ++i)
    label_[i] = bestSupported(static_cast<int>(i), discriminating, confirming);
  if (words_)
    labelByWords(blobs);
  for (int round = 0; round < 16; ++round)
  {
    grow_.clear();
    for (size_t i = 0; i < blobs.size(); ++i)
      if (label_[i] < 0 && cand_begin_[i] != cand_begin_[i + 1])
        growByGeometry(blobs, static_cast<int>(i), confirming);
    if (!applyGrowth())
      break;
  }
  finishLabels(result);
}

void Decoder::countSupport(const std::vector<Blob>& blobs)
{
  // Support: a neighbour that has the adjacent primitive among its tight candidates, at a similar
  // depth. Only a neighbour whose own geometry fits (a tight candidate) lends support.
  const float step = static_cast<float>(config_.max_depth_step);
  for (size_t i = 0; i < blobs.size(); ++i)
  {
    const int32_t k0 = cand_begin_[i], k1 = cand_begin_[i + 1];
    for (int32_t k = k0; k < k1; ++k)
      cands_[static_cast<size_t>(k)].bits = 0;
    for (int d = 0; d < 4 && k0 != k1; ++d)
    {
      const int n = blobs[i].neighbour[d];
      if (n < 0)
        continue;
      // The neighbour's few candidates are scanned whole, without early exits (they mispredicted);
      // a blob lists each primitive at most once, so the match found is findCandidate's.
      const int32_t j0 = cand_begin_[static_cast<size_t>(n)], j1 = cand_begin_[static_cast<size_t>(n) + 1];
      for (int32_t k = k0; k < k1; ++k)
      {
        Candidate& c = cands_[static_cast<size_t>(k)];
        const int q = ((c.edges >> d) & 1) ? c.primitive + adjacent_step_[d] : -1;
        int32_t kn = k;  // a stand-in that never supports: it is not q
        for (int32_t j = j0; j < j1; ++j)
          kn = cands_[static_cast<size_t>(j)].primitive == q ? j : kn;
        const Candidate& m = cands_[static_cast<size_t>(kn)];
        const bool support = (kn != k) & m.tight & (std::abs(m.depth - c.depth) <= step * c.depth);
        c.bits |= static_cast<uint8_t>(support << d);
      }
    }
  }
}

inline int Decoder::bestSupported(int blob, uint8_t discriminating, uint8_t confirming) const
{
  // The candidate that alone has the best support, with enough of it.
  const int32_t k0 = cand_begin_[static_cast<size_t>(blob)], k1 = cand_begin_[static_cast<size_t>(blob) + 1];
  if (k0 == k1)
    return -1;
  int best = -1, best_support = -1, ties = 0;
  for (int32_t k = k0; k < k1; ++k)
  {
    const int support = popcount4(cands_[static_cast<size_t>(k)].bits);
    if (support > best_support)
    {
      best_support = support;
      best = k;
      ties = 0;
    }
    else if (support == best_support)
      ++ties;
  }
  const Candidate& c = cands_[static_cast<size_t>(best)];
  const bool unique = (k1 - k0) == 1;
  const int confirm = popcount4(static_cast<uint8_t>(c.bits & confirming));
  const int discr = popcount4(static_cast<uint8_t>(c.bits & discriminating));
  if (ties > 0 || confirm < 1 || !c.tight)
    return -1;
  // A rival only one support short that fits the epipolar geometry about as well (or better) is
  // not ruled out: a blob's biased centroid or one false witness could make that difference. The
  // centroid of a blob cut by the image border may be off by its cut, too.
  const float rival_margin = kRivalEpipolarMargin + cut_[static_cast<size_t>(blob)];
  for (int32_t k = k0; k < k1; ++k)
  {
    const Candidate& r = cands_[static_cast<size_t>(k)];
    if (k != best && popcount4(r.bits) >= best_support - 1 && r.epipolar <= c.epipolar + rival_margin)
      return -1;
  }
  if (!unique && (discr < 1 || best_support < config_.min_support))
    return -1;
  if (unique && best_support < std::min(config_.min_support, 2))
    return -1;
  return best;
}

inline int Decoder::wordOf(const std::vector<Blob>& blobs, size_t i) const
{
  const Blob& b = blobs[i];
  int shape[4];
  for (int d = 0; d < 4; ++d)
  {
    const int n = b.neighbour[d];
    shape[d] = n >= 0 ? blobs[static_cast<size_t>(n)].shape : 0;
    if (shape[d] <= 0)
      return -1;
  }
  const sl_projector::GridPos g = words_->lookup(b.shape, shape[kNorth], shape[kWest], shape[kSouth], shape[kEast]);
  return g.valid() ? g.row * rig_.pattern.cols + g.col : -1;
}

void Decoder::labelByWords(const std::vector<Blob>& blobs)
{
  // The prototype's look-up: a blob whose four neighbours are all identified has a full word
  // (centre, N, W, S, E), which the direct 4^5 table turns into its primitive in O(1). The word
  // decodes a blob the first pass left open when that primitive is one of its tight candidates
  // (on its epipolar curve), is supported by a neighbour's geometry, and no candidate has more
  // support. Words read across a depth edge are caught by the validation (finishLabels()).
  for (size_t i = 0; i < blobs.size(); ++i)
  {
    if (label_[i] >= 0 || cand_begin_[i] == cand_begin_[i + 1])
      continue;
    const int p = wordOf(blobs, i);
    const int k = p >= 0 ? findCandidate(static_cast<int>(i), p) : -1;
    if (k < 0 || !cands_[static_cast<size_t>(k)].tight)
      continue;
    const int support = popcount4(cands_[static_cast<size_t>(k)].bits);
    bool better = false;
    for (int32_t j = cand_begin_[i]; j < cand_begin_[i + 1] && !better; ++j)
      better = j != k && popcount4(cands_[static_cast<size_t>(j)].bits) > support;
    if (support >= 2 && !better)
      label_[i] = k;
  }
}

inline void Decoder::growByGeometry(const std::vector<Blob>& blobs, int i, uint8_t confirming)
{
  // Growth: a blob next to decoded ones takes the primitive they imply, if that is one of its
  // candidates at a continuous depth, its shape is confirmed across the epipolar direction, and no
  // decoded neighbour disagrees. Decodes the pattern's border and blobs with ambiguous support.
  int implied = -1, agreeing = 0;
  for (int d = 0; d < 4; ++d)
  {
    const int n = blobs[static_cast<size_t>(i)].neighbour[d];
    if (n < 0 || label_[static_cast<size_t>(n)] < 0)
      continue;
    // The blob is n's neighbour in the opposite direction.
    const int p = adjacent(cands_[static_cast<size_t>(label_[static_cast<size_t>(n)])].primitive, kOpposite[d]);
    if (p < 0 || (implied >= 0 && p != implied))
      return;  // a conflict
    implied = p;
    ++agreeing;
  }
  const int k = implied >= 0 ? findCandidate(i, implied) : -1;
  if (k < 0)
    return;
  const Candidate& c = cands_[static_cast<size_t>(k)];
  const int confirm = popcount4(static_cast<uint8_t>(c.bits & confirming));
  if (!c.tight || popcount4(c.bits) < 2 || (confirm < 1 && agreeing < 2))
    return;
  // Another candidate with at least as much support makes the implication doubtful.
  for (int32_t j = cand_begin_[static_cast<size_t>(i)]; j < cand_begin_[static_cast<size_t>(i) + 1]; ++j)
    if (j != k && popcount4(cands_[static_cast<size_t>(j)].bits) >= popcount4(c.bits))
      return;
  grow_.push_back(i);
  grow_.push_back(k);
}

inline bool Decoder::applyGrowth()
{
  for (size_t g = 0; g < grow_.size(); g += 2)
    label_[static_cast<size_t>(grow_[g])] = grow_[g + 1];
  return !grow_.empty();
}

void Decoder::correspondByWords(DecodeResult& result)
{
  std::vector<Blob>& blobs = result.blobs;
  // The primitive each full word names. A misread shape gives a wrong word, but then the words of
  // its neighbours do not fit around it.
  word_.assign(blobs.size(), -1);
  for (size_t i = 0; i < blobs.size(); ++i)
    word_[i] = blobs[i].shape > 0 ? wordOf(blobs, i) : -1;
  // A word is taken when at least two neighbours' words name the adjacent primitives and the
  // geometry does not rule it out (one of the blob's candidates, within the loose tolerance).
  label_.assign(blobs.size(), -1);
  for (size_t i = 0; i < blobs.size(); ++i)
  {
    const int p = word_[i];
    if (p < 0)
      continue;
    uint8_t agree = 0;
    for (int d = 0; d < 4; ++d)
    {
      const int n = blobs[i].neighbour[d];
      if (n >= 0 && word_[static_cast<size_t>(n)] >= 0 && word_[static_cast<size_t>(n)] == adjacent(p, d))
        agree |= static_cast<uint8_t>(1 << d);
    }
    const int k = popcount4(agree) >= 2 ? findCandidate(static_cast<int>(i), p) : -1;
    if (k >= 0)
    {
      cands_[static_cast<size_t>(k)].bits = agree;  // the support the confidence reports
      label_[i] = k;
    }
  }
  for (int round = 0; round < 16; ++round)
  {
    grow_.clear();
    for (size_t i = 0; i < blobs.size(); ++i)
      if (label_[i] < 0 && blobs[i].shape != 0)
        growByWords(blobs, static_cast<int>(i));
    if (!applyGrowth())
      break;
  }
  finishLabels(result);
}

inline void Decoder::growByWords(const std::vector<Blob>& blobs, int i)
{
  // Growth to blobs without a full word (the pattern's border, gaps): the primitive the decoded
  // neighbours agree on, when the blob's shape and every neighbour's shape are the pattern's
  // there, and either two decoded neighbours or three shapes around confirm it.
  const std::vector<int>& values = pattern_.array().values();
  const Blob& b = blobs[static_cast<size_t>(i)];
  int implied = -1;
  uint8_t agreeing = 0;
  for (int d = 0; d < 4; ++d)
  {
    const int n = b.neighbour[d];
    if (n < 0 || label_[static_cast<size_t>(n)] < 0)
      continue;
    const int q = adjacent(cands_[static_cast<size_t>(label_[static_cast<size_t>(n)])].primitive, kOpposite[d]);
    if (q < 0 || (implied >= 0 && q != implied))
      return;  // a conflict
    implied = q;
    agreeing |= static_cast<uint8_t>(1 << d);
  }
  if (implied < 0 || values[static_cast<size_t>(implied)] != b.shape)
    return;
  // The shapes around must be the pattern's around the implied primitive (a partial word).
  int matches = 0, mismatches = 0;
  for (int d = 0; d < 4; ++d)
  {
    const int n = b.neighbour[d], q = adjacent(implied, d);
    if (n < 0 || blobs[static_cast<size_t>(n)].shape == 0)
      continue;
    if (q >= 0 && values[static_cast<size_t>(q)] == blobs[static_cast<size_t>(n)].shape)
      ++matches;
    else
      ++mismatches;
  }
  if (mismatches > 0 || (popcount4(agreeing) < 2 && matches < 3))
    return;
  const int k = findCandidate(i, implied);
  if (k >= 0)
  {
    cands_[static_cast<size_t>(k)].bits = agreeing;
    grow_.push_back(i);
    grow_.push_back(k);
  }
}

inline bool Decoder::rowSpellsPattern(const std::vector<Blob>& blobs, int i, int primitive) const
{
  const std::vector<int>& values = pattern_.array().values();
  int present = 0, mismatches = 0;
  // Along a row from blob j (primitive p): up to @p reach blobs west and east, and j itself.
  auto walkRow = [&](int j, int p, int reach)
  {
    ++present;
    mismatches += blobs[static_cast<size_t>(j)].shape != values[static_cast<size_t>(p)];
    for (int d : { kWest, kEast })
    {
      int jj = j, pp = p;
      for (int k = 0; k < reach; ++k)
      {
        jj = blobs[static_cast<size_t>(jj)].neighbour[d];
        pp = adjacent(pp, d);
        if (jj < 0 || pp < 0)
          break;
        ++present;
        mismatches += blobs[static_cast<size_t>(jj)].shape != values[static_cast<size_t>(pp)];
      }
    }
  };
  walkRow(i, primitive, kRowCheck);
  // The rows above and below, where the blob has such neighbours.
  for (int d : { kNorth, kSouth })
  {
    const int j = blobs[static_cast<size_t>(i)].neighbour[d], p = adjacent(primitive, d);
    if (j >= 0 && p >= 0)
      walkRow(j, p, kRowCheck / 2);
  }
  // Six blobs all right, or nine with one misread: a wrong identity passes with odds of about 1e-3
  // (random shapes), before the support and epipolar checks. Rows blurred so much that some shapes
  // read wrong: twelve with two misread, fifteen with three (odds of 4e-5 and 1e-5).
  return (present >= 6 && mismatches == 0) || (present >= 9 && mismatches <= 1) || (present >= 12 && mismatches <= 2) ||
         (present >= 15 && mismatches <= 3);
}

void Decoder::finishLabels(DecodeResult& result)
{
  std::vector<Blob>& blobs = result.blobs;
  const int cols = rig_.pattern.cols;
  // Blobs split out of merged ones, and cells read from a saturated band's outline, are identified
  // with less certainty (in the harshest blur and overexposure most read wrong): the shapes along
  // the row must spell the pattern's row.
  for (size_t i = 0; i < blobs.size(); ++i)
    if (label_[i] >= 0 && blobs[i].level > 0 &&
        !rowSpellsPattern(blobs, static_cast<int>(i), cands_[static_cast<size_t>(label_[i])].primitive))
      label_[i] = -1;

  // Validation: a decoded blob whose decoded neighbours mostly contradict it is undone.
  for (size_t i = 0; i < blobs.size(); ++i)
  {
    if (label_[i] < 0)
      continue;
    const int p = cands_[static_cast<size_t>(label_[i])].primitive;
    int agree = 0, disagree = 0;
    for (int d = 0; d < 4; ++d)
    {
      const int n = blobs[i].neighbour[d];
      if (n < 0 || label_[static_cast<size_t>(n)] < 0)
        continue;
      const int q = cands_[static_cast<size_t>(label_[static_cast<size_t>(n)])].primitive;
      if (q == adjacent(p, d))
        ++agree;
      else
        ++disagree;
    }
    // A part of a merged row or a band cell needs a decoded neighbour that agrees: alone, a few
    // misread shapes around it can spell a wrong column (it is never the only light there).
    if ((disagree > 0 && disagree >= agree) || (blobs[i].level > 0 && agree == 0))
      blobs[i].support = -1;  // mark; applied below so the check is order independent
  }
  for (size_t i = 0; i < blobs.size(); ++i)
    if (blobs[i].support < 0)
    {
      label_[i] = -1;
      blobs[i].support = 0;
    }

  // A primitive claimed by two blobs is trusted for neither.
  std::vector<int32_t>& owner = owner_;
  for (size_t i = 0; i < blobs.size(); ++i)
    if (label_[i] >= 0)
    {
      int32_t& o = owner[static_cast<size_t>(cands_[static_cast<size_t>(label_[i])].primitive)];
      o = (o == -1) ? static_cast<int32_t>(i) : -2;
    }
  for (size_t i = 0; i < blobs.size(); ++i)
  {
    if (label_[i] < 0)
      continue;
    const Candidate& c = cands_[static_cast<size_t>(label_[i])];
    if (owner[static_cast<size_t>(c.primitive)] == -2)
    {
      label_[i] = -1;
      continue;
    }
    Blob& b = blobs[i];
    b.row = c.primitive / cols;
    b.col = c.primitive % cols;
    b.support = popcount4(c.bits);
    b.epipolar_error = c.epipolar;
    ++result.decoded;
  }
  // Reset the owner table for the next frame (touching only what could have been set).
  for (const Candidate& c : cands_)
    owner[static_cast<size_t>(c.primitive)] = -1;
}

void Decoder::computeDepth(DecodeResult& result)
{
  const int cols = rig_.pattern.cols;
  for (size_t i = 0; i < result.blobs.size(); ++i)
  {
    Blob& b = result.blobs[i];
    b.valid = false;
    if (!b.decoded())
      continue;
    const int p = b.row * cols + b.col;
    const Eigen::Vector3d& ray = rays_[i];  // cameraRay(b.u, b.v), z = 1: decoded blobs had candidates
    double z = std::numeric_limits<double>::quiet_NaN();
    switch (config_.depth_mode)
    {
      case DepthMode::Triangulation:
        z = cand_z_[static_cast<size_t>(label_[i])];  // the ray-ray approach of the candidate's test
        break;
      case DepthMode::Rational:
      {
        const sl_projector::DepthModel& m = rig_.tables.rational[static_cast<size_t>(p)];
        if (m.valid)
          z = m.depth(b.u);
        break;
      }
      case DepthMode::Linear:
      {
        const sl_projector::DepthModel& m = rig_.tables.linear[static_cast<size_t>(p)];
        if (m.valid)
          z = m.depth(b.u);
        break;
      }
    }
    if (!std::isfinite(z) || z < config_.min_depth || z > config_.max_depth)
      continue;
    // An outline cell's margin is in pixels (lopsided against straight edge), an NCC margin in
    // correlation units.
    const bool outline = b.level == BlobDetector::kBandLevel;
    const float shape_term = std::min(1.f, outline ? b.margin / 2.f : b.margin / 0.3f);
    const float support_term = static_cast<float>(b.support) / 4.f;
    const float epipolar_term = std::max(0.f, 1.f - b.epipolar_error / static_cast<float>(config_.epipolar_tolerance));
    // How it was identified: a blob split out of a merged one, or read from a saturated outline, is
    // less certain than one found whole (the row check stands behind it, not its own shape).
    const float method = outline ? kOutlineWeight : b.level > 0 ? kSplitWeight : 1.f;
    b.confidence = method * (shape_term + support_term + epipolar_term) / 3.f;
    if (b.confidence < config_.min_confidence)
      continue;
    b.x = static_cast<float>(ray.x() * z);
    b.y = static_cast<float>(ray.y() * z);
    b.z = static_cast<float>(z);
    b.valid = true;
    ++result.valid;
  }
}

}  // namespace sl_decoder
