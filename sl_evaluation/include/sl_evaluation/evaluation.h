#pragma once
/// @file evaluation.h
/// @brief Scores decoding against the simulator's ground truth (ROS-free; uses the sl_sim renderer).

#include <string>
#include <vector>

#include "sl_decoder/decoder.h"
#include "sl_sim/renderer.h"
#include "sl_sim/scene.h"

namespace sl_evaluation
{

/// @brief Decoding quality of one or more frames.
struct EvalStats
{
  int frames = 0;                     ///< frames added
  int visible = 0;                    ///< primitives the camera sees well enough to decode (ground truth)
  int identified = 0;                 ///< blobs whose shape was identified
  int decoded = 0;                    ///< blobs given a (row, col)
  int valid = 0;                      ///< 3D points produced
  int valid_visible = 0;              ///< correct points on visible primitives (the part of valid that visible counts)
  int wrong = 0;                      ///< points whose (row, col) is not the primitive lighting that pixel
  int unverifiable = 0;               ///< points where the ground truth has no projector light nearby
  int near_points = 0;                ///< valid points on surfaces 15+ mm in front of the frame's background
  double sum_abs_error = 0.0;         ///< sum of |depth error| over points with ground-truth depth, m
  double max_abs_error = 0.0;         ///< m
  int with_depth = 0;                 ///< points that have a ground-truth depth
  std::vector<float> abs_errors;      ///< |depth error| of each point that has a ground-truth depth, m
  std::vector<float> decode_seconds;  ///< time in Decoder::decode per frame, s (evaluateScene; wall clock)

  /// @brief Share of the visible primitives that gave a correct point, percent (at most 100; points on
  /// primitives seen only in part, at borders and depth edges, come on top: valid - valid_visible).
  double validPercent() const { return visible > 0 ? 100.0 * valid_visible / visible : 0.0; }
  /// @brief Mean |depth error|, mm.
  double meanErrorMm() const { return with_depth > 0 ? 1000.0 * sum_abs_error / with_depth : 0.0; }
  /// @brief Max |depth error|, mm.
  double maxErrorMm() const { return 1000.0 * max_abs_error; }
  /// @brief Median decode time per frame, ms (robust to other jobs on a shared machine); 0 when not timed.
  double decodeMs() const;
  /**
   * @brief |depth error| that @p percent % of the points with ground-truth depth do not exceed, mm
   * (nearest rank: 50 the median, 95 the 95th percentile, 100 the max); 0 without such points.
   * @throws std::invalid_argument if @p percent is not in (0, 100].
   */
  double errorPercentileMm(double percent) const;
  /// @brief Adds another frame's statistics.
  void add(const EvalStats& other);
};

/**
 * @brief Compares a decode with the renderer's ground truth.
 *
 * A primitive is visible when the camera pixels lit by its box number at least 80% of the median
 * count of all lit primitives and their depths lie within 2% (at least 10 mm) of each other: the
 * camera sees it whole, on one surface (not cut by the image border, an occlusion or a corner). A point is wrong when
 * the ground-truth projector coordinates around its centroid (within 1.5 px) are lit but none lies in the box (with a 1
 * px margin) of the decoded primitive. The depth error compares the point's z with the ground-truth depth at its
 * centroid.
 */
EvalStats evaluateFrame(const sl_projector::Pattern& pattern, const sl_sim::RenderOutput& truth,
                        const sl_decoder::DecodeResult& result);

/// @brief One evaluated scene of sl_eval.
struct SceneReport
{
  std::string scene;  ///< scene file stem
  std::string model;  ///< depth model
  EvalStats stats;    ///< summed over the frames
};

/// @brief Camera distances of the near-range rows (0.35, 0.40, 0.45 m) and of the farther planes
/// they are compared with (0.55, 0.70, 0.90, 1.20 m): sl_eval's `--near-far` planes.
const std::vector<double>& nearFarDistances();

/**
 * @brief Renders @p scene_path with the default simulator settings for @p frames seeds, decodes
 * each frame with @p config and scores it.
 * @throws std::runtime_error / SceneFileError / RigFileError for unreadable inputs.
 */
SceneReport evaluateScene(const sl_projector::Rig& rig, const std::string& scene_path,
                          const sl_decoder::DecoderConfig& config, int frames = 1,
                          const sl_sim::SimSettings& settings = sl_sim::SimSettings());

/**
 * @brief A white plane (2 x 2 m, albedo @p albedo) facing the robot at @p camera_distance m from
 * the camera along the robot's x axis, standing on a grey textured floor: the near-range scene.
 */
sl_sim::Scene planeScene(const sl_projector::Rig& rig, double camera_distance, double albedo = 0.8);

/**
 * @brief As evaluateScene(), for a scene built in code; @p name is reported as the scene.
 * @param seed noise seed of the first frame (frame f uses seed + f).
 * The first frame is decoded once untimed (warm-up: the decoder's buffers grow to size), then every
 * frame's decode is timed into EvalStats::decode_seconds.
 */
SceneReport evaluateScene(const sl_projector::Rig& rig, const sl_sim::Scene& scene, const std::string& name,
                          const sl_decoder::DecoderConfig& config, int frames = 1,
                          const sl_sim::SimSettings& settings = sl_sim::SimSettings(), uint64_t seed = 1000);

/// @brief The file name of @p path without its directory and ".yaml".
std::string sceneStem(const std::string& path);

/// @brief Default locations compiled in: the scenes directory and the default rig file.
std::string defaultScenesDir();
/// @brief The default rig (calibration) file.
std::string defaultRigFile();

/**
 * @brief The alphabetically first scene file of the scenes directory whose name starts with
 * @p parts[0] and contains every other string of @p parts (for example {"plane_700"}).
 * @throws std::runtime_error if there is none.
 */
std::string findScene(const std::vector<std::string>& parts);

}  // namespace sl_evaluation
