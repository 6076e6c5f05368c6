#pragma once
/// @file decoder.h
/// @brief The decoding pipeline: camera image to decoded primitives with 3D points (ROS-free).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_decoder/blob.h"
#include "sl_decoder/blob_detector.h"
#include "sl_decoder/decoder_config.h"
#include "sl_decoder/epipolar_index.h"
#include "sl_decoder/ray_approach.h"
#include "sl_decoder/shape_classifier.h"
#include "sl_rig/pattern.h"
#include "sl_rig/word_table.h"
#include "sl_rig/rig.h"

namespace sl_decoder
{

/// @brief Wall-clock time of each stage of the last decode, ms.
struct StageTimes
{
  double detect = 0.0;      ///< thresholding, labelling, filtering, centroids
  double classify = 0.0;    ///< shape identification
  double candidates = 0.0;  ///< epipolar candidates per blob
  double neighbours = 0.0;  ///< neighbour search
  double correspond = 0.0;  ///< support, acceptance, validation
  double depth = 0.0;       ///< 3D points
  double total = 0.0;       ///< everything
};

/// @brief Everything one decode produces. Reused across frames (no allocation after warm-up).
struct DecodeResult
{
  std::vector<Blob> blobs;  ///< every blob that passed the filters; decoded ones have row >= 0
  int identified = 0;       ///< blobs whose shape was identified
  int decoded = 0;          ///< blobs with a (row, col)
  int valid = 0;            ///< blobs with a 3D point (and confidence >= min_confidence)
  StageTimes times;         ///< per-stage timing
};

/**
 * @brief Decodes camera images of the projected pattern.
 *
 * Pipeline (the prototype's, with the geometric additions):
 *  1. local mean threshold and 8-connected labelling with speckle, band and size filters;
 *  2. intensity-weighted sub-pixel centroid;
 *  3. shape identification by NCC against the four templates, with a margin;
 *  4. candidates: the primitives of that shape whose epipolar curve (calibrated rig, full
 *     distortion) passes within the tolerance and whose depth is in range;
 *  5. neighbours N, W, S, E: the nearest blob in a window around the pattern's local step;
 *  6. correspondence: a candidate is supported by each neighbour that has the adjacent primitive
 *     among its own candidates at a similar depth. Along the epipolar direction (usually the rows)
 *     candidates differ, so support there discriminates; across it, support confirms the shape.
 *     A blob takes the candidate that is the only one with the best support, if it has at least
 *     one confirming neighbour and min_support in all (a unique candidate needs only the
 *     confirmation). Then decoding grows: a blob next to decoded ones takes the primitive they
 *     imply when it is among its candidates, is confirmed and nothing disagrees. Finally decoded
 *     neighbours that contradict each other, and primitives claimed twice, are undone. Blobs whose
 *     size is far from the frame's median (cut by an edge, merged) are not decoded. This subsumes
 *     the prototype's full-word lookup and still decodes primitives with missing neighbours (the
 *     pattern's border, thin objects, depth edges) when the evidence leaves one candidate;
 *  7. depth: ray-ray triangulation with the projector ray of the decoded primitive, or the
 *     per-primitive rational or linear tables of a plane calibration.
 *
 * Near range (DecoderConfig::split_merged): blobs merged by defocus and overexposure are split at
 * raised thresholds, cut at the pattern's pitch, or (saturated rows) read from their outline
 * (BlobDetector); such blobs are decoded only where the shapes around them spell the pattern.
 *
 * Confidence (0..1) is the mean of the shape margin (saturating at 0.3; at 2 px for outline cells),
 * the support (of 4) and the epipolar fit (1 at the curve, 0 at the tolerance), times 0.8 for split
 * blobs and 0.6 for outline cells.
 */
class Decoder
{
public:
  /**
   * @brief Prepares the decoder for a rig.
   * @throws std::invalid_argument for an invalid config or rig (e.g. a camera over the image size
   * limits of sl_rig/limits.h), or a depth mode whose tables the rig lacks.
   */
  Decoder(const sl_projector::Rig& rig, const DecoderConfig& config = DecoderConfig());
  ~Decoder();

  /// @brief Decodes a CV_8UC1 image of the rig's camera size into @p result.
  /// @throws std::invalid_argument for another type or size.
  void decode(const cv::Mat& image, DecodeResult& result);

  /**
   * @brief The blur of the pattern in the image of a surface at @p depth m facing both lenses:
   * Gaussian sigma, camera px. Thin lens with the rig's optics (Rig::camera_optics,
   * Rig::projector_optics), camera and projector defocus and a base blur of 0.3 px each, the
   * projector's in camera px (times fx_camera / fx_projector). @p defocus_scale: lenses that blur
   * more or less than the rig file says.
   */
  double patternBlur(double depth, double defocus_scale = 1.0) const;

  /// @brief A primitive's width in the image, camera px (its share of the pattern's cell).
  double primitiveWidth() const;

  /// @brief The configuration.
  const DecoderConfig& config() const { return config_; }
  /// @brief The rig.
  const sl_projector::Rig& rig() const { return rig_; }
  /// @brief The pattern.
  const sl_projector::Pattern& pattern() const { return pattern_; }
  /// @brief The precomputed geometry.
  const EpipolarIndex& index() const { return *index_; }

private:
  struct Candidate
  {
    int32_t primitive;
    float depth;     // camera z, m
    float epipolar;  // px
    uint8_t bits;    // consistent neighbours, bit d for Direction d
    bool tight;      // within the epipolar tolerance (others, within twice it, only compete)
    uint8_t edges;   // bit d: the pattern has a primitive next to this one in Direction d
  };

  /// Fills the per-primitive tables (edges_, adjacent_step_, dir_dot_origin_) once for the rig.
  void preparePrimitives();
  /// Maps a cell read from a saturated band's outline into pattern terms and moves it to its centroid.
  void placeBandCell(Blob& b) const;
  /// Step 4: the candidates of every blob of typical size (cand_begin_, cands_, rays_).
  /// How far the centroid of a blob cut by the image border may be off, px (0 when it is whole);
  /// @p typical_w, @p typical_h: the typical blob's size.
  float borderCut(const Blob& b, float typical_w, float typical_h) const;
  void findCandidates(DecodeResult& result);
  /// The median box width and height of the identified blobs of each level (0 for none).
  void sizeMedians(const std::vector<Blob>& blobs, float* median_w, float* median_h);
  /// Blob level -> the index of its size statistics.
  static size_t levelOf(const Blob& b) { return std::min(static_cast<size_t>(b.level), kSizeLevels - 1); }
  /// Writes the candidates of blob @p bi (unit camera ray @p unit, look-up ranges_) into cands_ from
  /// @p used on, growing the buffer as needed; returns the new count.
  size_t appendCandidates(size_t bi, const Eigen::Vector3d& unit, size_t used);
  /// Writes candidate @p p with approach @p r into slot @p used; returns @p used + 1 when it is
  /// one (in the depth range, within twice the epipolar tolerance), else @p used.
  size_t keepCandidate(int32_t p, const RayApproach& r, size_t used);
  /// Sorts the identified blobs into the neighbour grid (grid_start_, grid_items_).
  void fillGrid(const std::vector<Blob>& blobs);
  /// A neighbour window: a parallelogram along one direction's step (see findNeighbours()).
  struct NeighbourWindow
  {
    float sx, sy;            // step, px
    float ax, ay, cx, cy;    // unit along, unit across
    float len, across;       // step length, length of the across step
    float amin, amax, cmax;  // accepted along (in steps) and across (in across steps)
    float mid, hx, hy;       // window centre in steps, bounding-box half size, px
  };
  /// The cost of no neighbour: every blob in a window costs less.
  static constexpr float kNoCost = 1e30f;
  /// The cost of a blob at (dx, dy) from the centre as the neighbour in window @p w; infinite outside
  /// the window (NaN for NaN input). Neither ever beats kNoCost.
  static float windowCost(float dx, float dy, const NeighbourWindow& w)
  {
    const float a = (dx * w.ax + dy * w.ay) / w.len;
    const float c = std::abs(dx * w.cx + dy * w.cy) / w.across;
    const float cost = (a - 1.f) * (a - 1.f) * w.len * w.len + c * c * w.across * w.across;
    const bool inside = !(a < w.amin) & !(a > w.amax) & !(c > w.cmax);
    return inside ? cost : std::numeric_limits<float>::infinity();
  }
  /// The four directions' windows, from the pattern's steps and the config.
  void neighbourWindows(NeighbourWindow* win) const;
  /// Step 5: each identified blob's nearest blob in each direction's window, or -1.
  void findNeighbours(DecodeResult& result);
  /// The blob of least windowCost() in window @p w of blob @p i (the first in scan order among
  /// equals), or -1; offers every blob found to the window of direction @p mirrored.
  int searchWindow(std::vector<Blob>& blobs, int i, const NeighbourWindow& w, int mirrored);
  /// Makes blob @p i blob @p n's neighbour in direction @p d (west or north) if it beats the best
  /// offered so far at @p cost.
  void offer(std::vector<Blob>& blobs, int n, int d, int i, float cost);
  /// Step 6 (geometry first): support, the best supported candidate, full words, growth.
  void correspond(DecodeResult& result);
  /// Sets every candidate's support bits: the neighbours that have the adjacent primitive among
  /// their tight candidates at a similar depth.
  void countSupport(const std::vector<Blob>& blobs);
  /// The candidate of @p blob that alone has the best support, with enough of it, or -1.
  int bestSupported(int blob, uint8_t discriminating, uint8_t confirming) const;
  /// Decodes by full words the blobs the first pass left open (words_ must exist).
  void labelByWords(const std::vector<Blob>& blobs);
  /// Queues in grow_ the primitive the decoded neighbours of blob @p i imply, if its geometry fits.
  void growByGeometry(const std::vector<Blob>& blobs, int i, uint8_t confirming);
  /// Step 6 for DecoderConfig::identify_by_words: full words confirmed by neighbours, then growth.
  void correspondByWords(DecodeResult& result);
  /// Queues in grow_ the primitive the decoded neighbours of blob @p i imply, if the shapes fit.
  void growByWords(const std::vector<Blob>& blobs, int i);
  /// The primitive the full word of blob @p i (its shape and its four neighbours') names, or -1.
  int wordOf(const std::vector<Blob>& blobs, size_t i) const;
  /// Applies the (blob, candidate) pairs of grow_ to label_; false when there were none.
  bool applyGrowth();
  /// Undoes labels contradicted by their decoded neighbours and primitives claimed twice, then
  /// writes the rest into the blobs.
  void finishLabels(DecodeResult& result);
  /// True when the shapes of the blobs around blob @p i (kRowCheck east and west, half as many in
  /// the rows above and below; fewer at the pattern's border) are the pattern's around
  /// @p primitive: six with no exception or nine with one.
  bool rowSpellsPattern(const std::vector<Blob>& blobs, int i, int primitive) const;
  static constexpr int kRowCheck = 4;
  /// The candidate of @p blob for @p primitive, or -1 (inline: the correspondence's inner loop).
  int findCandidate(int blob, int primitive) const
  {
    const int32_t k1 = cand_begin_[static_cast<size_t>(blob) + 1];
    for (int32_t k = cand_begin_[static_cast<size_t>(blob)]; k < k1; ++k)
      if (cands_[static_cast<size_t>(k)].primitive == primitive)
        return static_cast<int>(k);
    return -1;
  }
  /// The primitive adjacent to @p p (a primitive) in direction @p d, or -1 outside the pattern.
  int adjacent(int p, int d) const { return (edges_[static_cast<size_t>(p)] >> d) & 1 ? p + adjacent_step_[d] : -1; }
  void computeDepth(DecodeResult& result);

  sl_projector::Rig rig_;
  DecoderConfig config_;
  sl_projector::Pattern pattern_;
  std::unique_ptr<EpipolarIndex> index_;
  std::unique_ptr<sl_projector::WordTable> words_;  // null when the pattern's words repeat
  BlobDetector detector_;
  ShapeClassifier classifier_;
  // Per-primitive geometry, fixed for the rig.
  std::vector<uint8_t> edges_;                // Candidate::edges of each primitive
  int adjacent_step_[4] = {};                 // index step to the adjacent primitive per Direction
  std::vector<double> dir_dot_origin_;        // projectorDirection(p) . projectorOrigin()
  std::array<double, 5> band_cell_offset_{};  // per shape 1..4: placeBandCell()'s centroid offset, pattern px
  // Per-frame work buffers.
  std::vector<int32_t> cand_begin_;  // blobs + 1
  std::vector<Candidate> cands_;
  std::vector<double> cand_z_;          // candidate -> its depth as computed (the triangulated depth)
  std::vector<Eigen::Vector3d> rays_;   // blob -> cameraRay of its centroid (typical_ blobs)
  std::vector<Eigen::Vector3d> units_;  // blob -> that ray normalised (typical_ blobs)
  std::vector<uint8_t> typical_;        // blob -> identified and of typical size: has candidates
  std::vector<float> cut_;              // blob -> borderCut() (typical_ blobs), px
  std::vector<std::pair<const int32_t*, const int32_t*>> ranges_;  // blob -> EpipolarIndex::candidates()
  struct GridItem
  {
    float u, v;  // the blob's centroid, px
    int32_t j;   // the blob
  };
  std::vector<int32_t> grid_start_, grid_fill_;  // CSR offsets per cell, fill positions
  std::vector<GridItem> grid_items_;             // identified blobs, cell by cell
  std::vector<float> offered_cost_;              // blob * 2 + (west ? 1 : 0) -> cost of the best blob offered
  std::vector<uint64_t> offered_key_;            // and its scan order: cell << 32 | blob
  std::vector<size_t> blob_cell_;                // blob -> its grid cell (identified blobs)
  std::vector<int32_t> owner_;                   // primitive -> blob, for duplicate detection
  std::vector<int32_t> label_;                   // blob -> candidate index (working copy)
  std::vector<int32_t> grow_;                    // (blob, candidate) pairs decoded in a growth round
  std::vector<int32_t> word_;                    // blob -> primitive its full word names, or -1 (identify_by_words)
  static constexpr size_t kSizeLevels = 8;       // Blob::level values with their own median (more share the last)
  std::vector<int> sizes_w_[kSizeLevels], sizes_h_[kSizeLevels];  // box sizes of identified blobs per level
  int grid_w_ = 0, grid_h_ = 0;
  size_t grid_cells_ = 0;  // grid_w_ * grid_h_, computed once in 64 bits
  double grid_cell_ = 1.0;
};

}  // namespace sl_decoder
