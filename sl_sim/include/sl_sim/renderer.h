#pragma once
/// @file renderer.h
/// @brief The projector-camera renderer: what the rig's camera sees of a scene lit by the rig's
/// projector (ROS-free).

#include <cstdint>
#include <memory>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "sl_sim/scene.h"
#include "sl_sim/sim_settings.h"
#include "sl_rig/rig.h"

namespace sl_sim
{

/// @brief The products of one rendered frame (buffers are reused from frame to frame).
struct RenderOutput
{
  cv::Mat image;  ///< CV_8UC1, camera size: the simulated camera image
  /// CV_32FC1: ground-truth depth (z of the camera optical frame, m) of the surface seen through each
  /// pixel centre, NaN where the ray meets nothing (REP 118).
  cv::Mat depth;
  /// CV_32FC2: the projector frame-buffer pixel (x, y) lighting the surface seen through each pixel
  /// centre (exact geometry, no blur), NaN where that surface is in the projector's shadow, faces
  /// away from the projector or lies outside the projector frame.
  cv::Mat projector_coords;
};

/**
 * @brief Renders camera images of a scene lit by the structured-light projector.
 *
 * Image formation, in order: one ray per camera pixel centre (and more rays per pixel on edges
 * between objects, faces, shadows and texture squares, see SimSettings::antialias); the projector's
 * shadows (a point the projector cannot see gets no pattern); projector irradiance
 * P cos(theta) / d^2 relative to its focus distance, with lens falloff across the frame; the
 * pattern pre-filtered by the projector pixel footprint and the projector's defocus (a Gaussian
 * pyramid sampled trilinearly); ambient light; albedo and texture; a normalised Blinn-Phong
 * specular lobe; camera defocus (blur levels blended by depth) and veiling glare; vignetting and
 * exposure; shot and read noise (approximately Gaussian, from a hash of the seed and the pixel
 * index); 12-bit quantisation, gamma, 8-bit output with saturation.
 *
 * All computation is in the camera optical frame, in tiles of 16 x 16 rays processed by
 * data-parallel kernels (AVX2 where the CPU has it). Not thread-safe; one frame at a time.
 */
class Renderer
{
public:
  /**
   * @param rig the projector-camera rig (camera and projector models, projector pose).
   * @param settings image-formation parameters.
   * @throws std::invalid_argument for invalid settings (the message names the field) or rig.
   */
  explicit Renderer(const sl_projector::Rig& rig, const SimSettings& settings = SimSettings());
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /**
   * @brief Renders one frame.
   *
   * @param scene the scene (world frame).
   * @param pattern_mono8 the projector frame buffer (CV_8UC1, the rig's projector size); the
   *        pre-filtered pattern is cached and rebuilt only when the content changes.
   * @param camera_optical_in_world pose of the camera optical frame in the world.
   * @param seed noise seed: the same seed gives the same bytes.
   * @param out the products; its buffers are reused (no allocation after the first frame).
   * @throws std::invalid_argument if the pattern is not CV_8UC1 of the projector's size.
   */
  void render(const Scene& scene, const cv::Mat& pattern_mono8, const Eigen::Isometry3d& camera_optical_in_world,
              uint64_t seed, RenderOutput& out);

  /// @brief The rig.
  const sl_projector::Rig& rig() const;
  /// @brief The settings.
  const SimSettings& settings() const;

  /// @brief Camera blur (Gaussian sigma, camera px) for a surface at @p depth m (base and defocus).
  double cameraBlurSigma(double depth) const;
  /// @brief Projector blur on a surface at @p distance m along the projector axis (Gaussian sigma,
  /// projector px; base and defocus, without the pixel footprint).
  double projectorBlurSigma(double distance) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/**
 * @brief The camera optical frame in the world when the robot's platform_edge frame is at
 * @p platform_edge_in_world: platform_edge_in_world * rig.mount.cameraOpticalInParent().
 */
Eigen::Isometry3d cameraPoseInWorld(const sl_projector::Rig& rig,
                                    const Eigen::Isometry3d& platform_edge_in_world = Eigen::Isometry3d::Identity());

/// @brief Converts a RigidTransform to an Eigen isometry.
Eigen::Isometry3d toIsometry(const sl_projector::RigidTransform& transform);

}  // namespace sl_sim
