#pragma once
/// @file ray_classifier.h
/// @brief Per-ray outcomes: what every projected primitive says about free and occupied space in
/// one frame (doc/world_model.md section 1; ROS-free).

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "sl_decoder/decoder.h"
#include "sl_decoder/decoder_config.h"
#include "sl_rig/rig.h"

namespace sl_decoder
{

/// @brief Outcome of one projector ray in one frame (values are stable: they go on the wire).
enum class RayState : uint8_t
{
  Decoded = 0,  ///< the decoder produced a valid point for it
  Floor = 1,    ///< its light is exactly where its ray meets the floor plane
  Dark = 2,     ///< no unexplained pattern light on the checked part of its segment
  Lit = 3,      ///< unexplained light on its segment that may be its own (an obstacle candidate)
  Unseen = 4    ///< nothing of its segment could be checked (outside the image or hidden)
};

/// @brief Number of RayState values.
constexpr int kRayStates = 5;

/// @brief "decoded", "floor", "dark", "lit" or "unseen" ("?" for anything else).
const char* toString(RayState s);

/**
 * @brief Tunables of the ray classifier. The contrast model: the pattern's contrast (DN above the
 * local background) on a surface of albedo a at camera depth z is a * C1 / z^2.
 */
struct RayConfig
{
  /// Darkest surface that must be seen, 0..1. Surfaces darker than this are invisible at the far
  /// end of the range, so `dark` means "no surface of albedo >= min_albedo". 0.1 is about black
  /// paint, dark fabric or a black plastic bin seen at an angle; darker (velvet, 0.02) is out of
  /// reach of this sensor at any useful distance: even at 0.5 m it shows a few DN, within the noise.
  double min_albedo = 0.1;
  /// Prior for C1: the light-map contrast (DN above the local background) of a white (albedo 1)
  /// surface at 1 m camera depth, facing the rig. Measured on the simulator's default settings: the
  /// median over the decoded blobs of a plane of albedo 0.8 at 1.0 m (3 seeds, 2631 blobs) is
  /// 76.2 DN, / 0.8 = 95 (README, "Ray outcomes"). Each frame raises it to its own lower bound.
  double pattern_contrast_1m = 95.0;
  /// Slant and blur allowance, (0, 1]: a surface counts as detected when its local contrast is at
  /// least this fraction of the nominal a * C1 / z^2.
  double light_fraction = 0.5;
  /// DN. Light-map contrast that noise alone reaches (measured: at most 4 to 6 DN in pattern-free
  /// frames of the simulator at the 99.99th percentile); below it nothing is called light, and beyond
  /// the depth where a min_albedo surface would fall below it the ray is not checked any further.
  double noise_floor = 8.0;
  /// m, camera z: far end of the checked segment (>= the decoder's min_depth, <= its max_depth).
  double max_range = 2.5;
  /// m, camera z: nearer than this, defocus smears the pattern into a uniform glow, so a block mean
  /// above the frame's dark level by the expected glow of a min_albedo surface, when the darkest block
  /// around or the mean above that block alone reaches it too (a glow, not a far wall's faint focused
  /// dots over dark gaps; the lit fraction of
  /// the pattern times light_fraction * min_albedo * C1 / z^2, at least twice noise_floor) counts as
  /// light too (0 disables it).
  double glow_max_depth = 0.5;
  /// DN: a light-map maximum at or above this (saturation) is light at every depth.
  double saturation_level = 250.0;

  /**
   * @brief Checks every field (not the relation to the decoder's depth range, see RayClassifier).
   * @throws std::invalid_argument whose message starts with the field name.
   */
  void validate() const;
};

/// @brief The outcome of one primitive's ray. Points are in the camera optical frame, m.
struct RayOutcome
{
  RayState state = RayState::Unseen;  ///< the outcome
  /// Camera z of the end point, m (NaN for unseen).
  float depth = std::numeric_limits<float>::quiet_NaN();
  /// Start of the free (or suspect) part of the ray: the projector centre for decoded and floor,
  /// the point at the decoder's min_depth for dark and lit; NaN for unseen.
  Eigen::Vector3f start = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  /// End of the free part: the surface point (decoded), the floor hit (floor), the end of the checked
  /// free part (dark) or the nearest depth the light allows (lit); NaN for unseen.
  Eigen::Vector3f end = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  int blob = -1;  ///< index of the decoded blob in DecodeResult::blobs, or -1
};

/**
 * @brief Gives every primitive (row, col) exactly one RayOutcome per frame.
 *
 * Precomputed per primitive: its projector ray, samples along it from the decoder's min_depth to
 * max_range uniformly in inverse depth (about 4 px apart in the image, one per light-map block),
 * their light-map blocks (full distortion), and its floor hit (z = 0 of the mount's parent frame)
 * with the camera pixels of the primitive's centre column and of the gaps beside it there.
 *
 * Per frame: a light map of 4 x 4 px blocks (the brightest 2 x 2 bin mean of the block minus the
 * smallest block mean of the 5 x 5 blocks around it, half the noise of a pixel maximum; near the
 * camera also the block's peak above the frame's dark level, for the glow of blurred surfaces), a
 * claim map (the boxes of decoded blobs with their depth, then the floor footprints) and a shape map
 * (identified blobs left undecoded). Floor test: the mean along the primitive's centre line on the
 * floor (it is sheared there) is above the background, the gap lines beside it are darker, and it is
 * no brighter than a white floor could be at that incidence and distance. Then the walk along each
 * remaining segment described in doc/world_model.md; a floor candidate is `floor` unless the walk
 * finds light that may be its own (and, when the walk could not check up to the floor, only with
 * clear floor light).
 *
 * C1 (the contrast of a white surface at 1 m) is max(prior, frame bound). The frame bound is the
 * 90th percentile over decoded blobs of their light-map contrast times z^2: each of these values is
 * at most C1 (an albedo cannot exceed 1), so the bound never overestimates C1; the percentile
 * keeps a specular highlight from raising it.
 *
 * Not thread-safe. No allocation after the first frame.
 */
class RayClassifier
{
public:
  /**
   * @brief Precomputes the geometry.
   * @throws std::invalid_argument for an invalid config (the message starts with the field name),
   *         also when max_range lies outside the decoder's [min_depth, max_depth].
   */
  RayClassifier(const sl_projector::Rig& rig, const DecoderConfig& decoder_config, const RayConfig& config);

  /**
   * @brief Classifies every primitive of a frame.
   * @param image the CV_8UC1 image that was decoded (camera size).
   * @param result its decode.
   * @param[out] outcomes rows * cols entries after the call, indexed row * cols + col.
   * @throws std::invalid_argument for an image of another type or size.
   */
  void classify(const cv::Mat& image, const DecodeResult& result, std::vector<RayOutcome>& outcomes);

  /// @brief The C1 used in the last frame (DN at 1 m for albedo 1).
  double lastC1() const { return c1_; }
  /// @brief The frame's own lower bound on C1 in the last frame (0 when nothing was decoded).
  double lastFrameBound() const { return frame_bound_; }
  /// @brief Primitives per state in the last frame, indexed by the RayState value.
  const std::array<int, kRayStates>& lastCounts() const { return counts_; }
  /// @brief Count of @p state in the last frame.
  int lastCount(RayState state) const { return counts_[static_cast<size_t>(state)]; }
  /// @brief The frame's dark level (DN) in the last frame.
  int lastDarkLevel() const { return dark_level_; }
  /// @brief Camera z beyond which a min_albedo surface is no longer detectable, last frame, m.
  double lastDetectableDepth() const { return detectable_depth_; }

  /// @brief Light-map contrast (block max minus neighbourhood min) of the block holding pixel (u, v).
  int blockContrast(int u, int v) const;
  /// @brief Number of samples of primitive @p index (0 when its segment starts outside the image).
  int samples(int index) const
  {
    const Primitive& p = prims_[static_cast<size_t>(index)];
    return p.end - p.begin;
  }
  /// @brief Camera z of primitive @p index's floor hit when it is in range and in view, else NaN.
  float floorDepth(int index) const { return prims_[static_cast<size_t>(index)].floor_z; }
  /// @brief The configuration.
  const RayConfig& config() const { return config_; }

  /// @brief Point of primitive @p index's ray at camera depth @p z, camera optical frame.
  Eigen::Vector3f pointAtDepth(int index, double z) const;
  /// @brief The projector centre (origin of every ray), camera optical frame.
  const Eigen::Vector3f& projectorCentre() const { return origin_; }

private:
  static constexpr int kShift = 2;   // 4 px blocks
  static constexpr int kRadius = 2;  // neighbourhood of the local minimum, blocks

  struct Sample
  {
    int32_t block;  // light-map block, -1 outside the image
    float z;        // camera depth, m
    float inv_z2;   // 1 / z^2
  };
  struct Primitive
  {
    int32_t begin = 0, end = 0;                               // samples
    uint8_t shape = 0;                                        // pattern value 1..4
    float floor_z = std::numeric_limits<float>::quiet_NaN();  // camera z of the floor hit, NaN: none
    float limit = std::numeric_limits<float>::infinity();     // camera z where the ray meets the floor
    float floor_gain = 0.f;  // cos(incidence) / z^2 at the floor hit: floor light <= C1 * floor_gain
    // On the floor (camera px): the rows v0..v1 the primitive covers and, at v0 and at v1, the
    // columns of its centre line (lit in every shape) and of the gaps left and right of it.
    int16_t v0 = 0, v1 = -1;
    float cu0 = 0.f, cu1 = 0.f, lu0 = 0.f, lu1 = 0.f, ru0 = 0.f, ru1 = 0.f;
    int16_t bx0 = 0, by0 = 0, bx1 = -1, by1 = -1;  // floor footprint, blocks (inclusive)
  };

  void precompute(const sl_projector::Rig& rig, const DecoderConfig& decoder_config);
  void precomputeFloor(const sl_projector::Rig& rig, const sl_projector::Pattern& pattern, int index, Primitive& p);
  bool precomputeFootprint(const sl_projector::Rig& rig, const sl_projector::RigidTransform& mount, double x, double y0,
                           double y1, Primitive& p) const;
  void buildLightMap(const cv::Mat& image);
  void buildClaims(const DecodeResult& result);
  void estimateC1(const DecodeResult& result);
  /// Means along the primitive's centre line and its two gap lines on the floor.
  void floorProfile(const cv::Mat& image, const Primitive& p, float& centre, float& left, float& right) const;
  /// Light on the primitive's floor centre line (DN above the background) when it passes the floor test, else 0.
  float floorLight(const cv::Mat& image, const Primitive& p) const;
  void claimFloor(const Primitive& p);
  /// Walks the floor candidates; the unconfirmed ones lose their claims (the map is rebuilt).
  void confirmFloors(const DecodeResult& result, std::vector<RayOutcome>& outcomes);
  // Why a walk along a segment ended.
  enum StopReason
  {
    kEnd,           // the image border or max_range
    kReachedFloor,  // the floor hit: a ray does not go through the floor
    kHidden,        // a nearer decoded or floor surface hides the rest
    kOther,         // another primitive's light on an unknown surface
    kUndetectable,  // a min_albedo surface would not be seen any further
    kLit            // light that may be its own
  };
  /// Walks the segment near to far; returns the sample where it stopped, sets the last free one.
  int walkSegment(const Primitive& p, int& last_free, int& stop) const;
  void walk(int index, RayOutcome& out);
  /// Turns lit ends that no neighbouring row confirms into the end of a free part (dark).
  void dropUnsupportedSuspects(std::vector<RayOutcome>& outcomes);
  /// Whether lit outcome @p i is confirmed: by a neighbouring row's end within kSupport (its own
  /// light only), or in the glow zone by a surface decoded just behind it nearby.
  bool confirmed(const std::vector<RayOutcome>& outcomes, int i) const;
  /// Whether @p pred(j) holds for a primitive j of the pattern rows above and below primitive @p i,
  /// at most @p span columns from it (the neighbourhood every confirmation rule searches).
  template <typename Pred>
  bool anyInNeighbourRows(int i, int span, Pred pred) const
  {
    const int r = i / cols_, c = i % cols_;
    for (int rr = r - 1; rr <= r + 1; rr += 2)
    {
      if (rr < 0 || rr >= rows_)
        continue;
      for (int cc = std::max(0, c - span); cc <= std::min(cols_ - 1, c + span); ++cc)
        if (pred(static_cast<size_t>(rr * cols_ + cc)))
          return true;
    }
    return false;
  }
  void setOutcome(RayOutcome& out, RayState state, int index, float z) const;

  RayConfig config_;
  int rows_ = 0, cols_ = 0;
  int width_ = 0, height_ = 0;
  float min_depth_ = 0.25f;
  Eigen::Vector3f origin_;
  std::vector<Eigen::Vector3f> directions_;
  std::vector<Primitive> prims_;
  std::vector<Sample> samples_;
  // Light map (blocks), per frame.
  int bw_ = 0, bh_ = 0;
  std::vector<uint8_t> bmax_;  // brightest 2 x 2 bin mean of the block
  std::vector<uint8_t> bmin_;  // block mean
  std::vector<uint8_t> lmin_;  // smallest block mean of the (2R+1)^2 blocks around: the background
  std::vector<uint8_t> tmp_;
  std::vector<uint8_t> pad_;          // a row of block means with a border of 255, for the minimum
  std::vector<float> claim_;          // nearest depth claiming the block, +inf when none
  std::vector<uint8_t> shape_;        // identified undecoded blob's shape covering the block, 0 none, 255 several
  std::vector<float> bounds_;         // per decoded blob: contrast * z^2
  std::vector<float> floor_light_;    // per primitive: floorLight() of this frame
  std::vector<int32_t> lit_free_;     // per primitive: the last free sample before its light (lit), -1 none
  std::vector<uint8_t> unsupported_;  // per primitive: a lit end no neighbouring row confirms
  std::vector<uint8_t> near_other_;   // per primitive: lit at light of another shape or the border, in the glow zone
  // Per-frame results.
  double c1_ = 0.0, frame_bound_ = 0.0, detectable_depth_ = 0.0;
  float k_ = 0.f;      // light_fraction * min_albedo * C1
  float duty_ = 0.3f;  // lit fraction of the projector frame: a fully blurred pattern's glow is this times its peak
  float inv_z2_min_ = 0.f;  // samples with 1/z^2 below this are beyond the detectable depth
  int dark_level_ = 0;
  std::array<int, kRayStates> counts_{};
};

}  // namespace sl_decoder
