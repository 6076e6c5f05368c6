#pragma once
/// @file calibration_simulation.h
/// @brief Calibration in simulation: renders the calibration views with the sl_sim simulator
/// (a wall at known distances, checkerboard views, calibration planes with a board) and measures a
/// calibrated rig against the simulator's true rig (ROS-free).

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "sl_calibration/camera_calibration.h"
#include "sl_calibration/plane_calibration.h"
#include "sl_evaluation/evaluation.h"
#include "sl_sim/renderer.h"
#include "sl_sim/scene.h"

namespace sl_evaluation
{

/// @brief The calibration scenes of the simulator (sl_sim/scenes/calib_*.yaml).
struct SimScenes
{
  std::string wall;                 ///< calib_wall.yaml: the plane for the plane calibration
  std::vector<std::string> boards;  ///< calib_board_*.yaml: checkerboard views for the camera
  std::vector<std::string> planes;  ///< calib_plane_*.yaml: calibration planes (board + pattern)
};

/**
 * @brief The calibration scenes in @p dir (default: the simulator's scenes directory), sorted.
 * @throws sl_calibration::CalibrationError if the wall or any plane scene is missing.
 */
SimScenes findSimScenes(const std::string& dir = "");

/// @brief The board every calib_* scene uses: the checkerboard texture of its first board object.
/// @throws CalibrationError if the scene has no checkerboard-textured plane.
sl_calibration::Board boardOfScene(const sl_sim::Scene& scene);

/**
 * @brief The pose of the robot's platform_edge in the world that puts the plane named "wall" of
 * @p wall_scene at @p distance, as defined by @p options (reference and normal; the wall must face
 * the robot along world -x, the robot looks along world +x).
 * @throws CalibrationError if the scene has no such wall, or the normal is PlaneNormal::Camera.
 */
Eigen::Isometry3d platformEdgeForDistance(const sl_projector::Rig& rig, const sl_sim::Scene& wall_scene,
                                          double distance, const sl_calibration::PlaneCalibrationOptions& options);

/// @brief @p scene with every texture removed (a board covered by a blank sheet).
sl_sim::Scene withoutTextures(const sl_sim::Scene& scene);

/**
 * @brief Renders calibration images of a (true) rig.
 *
 * Pattern images use the given settings (default: the simulator's defaults) and the rig's pattern.
 * Board images use the same settings with the room lights on (ambient `board_ambient`), the
 * projector showing black, and 16 rays per pixel on edges (a sensor integrates over its pixels; with
 * 4 rays the rendered corners are off by up to 0.25 px).
 */
class CalibrationSimulator
{
public:
  /// @param rig the true rig. @param settings image formation. @param board_ambient ambient light of board images.
  explicit CalibrationSimulator(const sl_projector::Rig& rig,
                                const sl_sim::SimSettings& settings = sl_sim::SimSettings(),
                                double board_ambient = 0.6);
  ~CalibrationSimulator();

  /// @brief Pattern image (and ground truth) of @p scene seen from the robot at @p platform_edge_in_world.
  const sl_sim::RenderOutput& renderPattern(const sl_sim::Scene& scene, const Eigen::Isometry3d& platform_edge_in_world,
                                            uint64_t seed);
  /// @brief Board image (lights on, projector dark) of @p scene from the default robot pose.
  const sl_sim::RenderOutput& renderBoard(const sl_sim::Scene& scene, uint64_t seed);
  /// @brief The pattern image of the wall at @p distance (see platformEdgeForDistance()).
  const sl_sim::RenderOutput& renderWall(const sl_sim::Scene& wall_scene, double distance,
                                         const sl_calibration::PlaneCalibrationOptions& options, uint64_t seed);

  /// @brief The true rig.
  const sl_projector::Rig& rig() const { return rig_; }

private:
  sl_projector::Rig rig_;
  sl_sim::SimSettings settings_;
  sl_sim::SimSettings board_settings_;
  std::unique_ptr<sl_sim::Renderer> renderer_;
  std::unique_ptr<sl_sim::Renderer> board_renderer_;
  cv::Mat pattern_, dark_;
  sl_sim::RenderOutput out_;
};

/// @brief Depth of two rigs compared on the same image (triangulation, primitives both decode).
struct DepthAgreement
{
  int points = 0;        ///< primitives decoded by both
  double mean_mm = 0.0;  ///< mean |z_a - z_b|, mm
  double max_mm = 0.0;   ///< max |z_a - z_b|, mm
  double mean_z = 0.0;   ///< mean depth of the points, m
};

/// @brief Decodes @p image with @p a and with @p b (triangulation) and compares the depths.
DepthAgreement compareDepth(const sl_projector::Rig& a, const sl_projector::Rig& b, const cv::Mat& image);

/// @brief Decodes a rendered frame with @p rig in @p mode and scores it against the ground truth.
EvalStats evaluateRendered(const sl_projector::Rig& rig, sl_decoder::DepthMode mode, const sl_sim::RenderOutput& truth);

}  // namespace sl_evaluation
