// The projector-camera renderer. Everything happens in the camera optical frame:
//  1. scene objects are moved into the camera frame and culled against 16 x 16 pixel tiles of the
//     camera, and of the projector frame (for shadow rays), in two levels (64 px, then 16 px);
//  2. per camera tile, one ray per pixel centre, traced as 256 "lanes" through data-parallel kernels
//     (lanes.h): nearest hit, surface (normal, albedo, texture), projector side (pixel, irradiance
//     P cos / d^2 with lens falloff, pattern blur from defocus and footprint), shadow rays to the
//     projector centre, trilinear lookup in the pre-blurred pattern pyramid, radiance with ambient
//     light and a Blinn-Phong lobe. This gives depth, projector coordinates and a radiance sample;
//  3. pixels on edges (object, face, shadow, texture square) get `antialias` rays;
//  4. camera defocus: blur levels of the radiance image (sigma 0.5 and 1 px at full, 2 px at half
//     and 4 px at quarter resolution) blended per pixel by depth; glare halo;
//  5. vignetting, exposure, shot and read noise (approximately Gaussian, from a seeded hash of the
//     pixel index), 12-bit quantisation, gamma, 8-bit output with saturation.
// All buffers are allocated in the constructor or on the first frame.
//
// The stages live in renderer_setup.cpp (buffers, tables, pattern pyramid), renderer_cull.cpp (1),
// renderer_trace.cpp (2, 3) and renderer_sensor.cpp (4, 5); renderer_impl.h holds the state.
#include "sl_sim/renderer.h"

#include <cmath>

#include "renderer_impl.h"

namespace sl_sim
{

Renderer::Renderer(const sl_projector::Rig& rig, const SimSettings& settings) : impl_(new Impl(rig, settings)) {}

Renderer::~Renderer() = default;

const sl_projector::Rig& Renderer::rig() const
{
  return impl_->rig;
}

const SimSettings& Renderer::settings() const
{
  return impl_->settings;
}

double Renderer::cameraBlurSigma(double depth) const
{
  const Impl& m = *impl_;
  const double defocus = m.cam_defocus_k * std::abs(1.0 / depth - 1.0 / m.settings.camera_focus_distance);
  return std::sqrt(m.settings.camera_base_blur * m.settings.camera_base_blur + defocus * defocus);
}

double Renderer::projectorBlurSigma(double distance) const
{
  const Impl& m = *impl_;
  const double defocus = m.proj_defocus_k * std::abs(1.0 / distance - 1.0 / m.settings.projector_focus_distance);
  return std::sqrt(m.settings.projector_base_blur * m.settings.projector_base_blur + defocus * defocus);
}

void Renderer::render(const Scene& scene, const cv::Mat& pattern_mono8,
                      const Eigen::Isometry3d& camera_optical_in_world, uint64_t seed, RenderOutput& out)
{
  Impl& m = *impl_;
  m.updatePattern(pattern_mono8);
  m.prepareScene(scene, camera_optical_in_world);
  m.cull(m.cam_tiles);
  m.cull(m.proj_tiles);
  out.image.create(m.H, m.W, CV_8UC1);
  out.depth.create(m.H, m.W, CV_32FC1);
  out.projector_coords.create(m.H, m.W, CV_32FC2);
  m.castPrimary(out);
  m.antialias();
  m.sensor(seed, out.depth, out.image);
}

Eigen::Isometry3d toIsometry(const sl_projector::RigidTransform& transform)
{
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = transform.rotation;
  iso.translation() = transform.translation;
  return iso;
}

Eigen::Isometry3d cameraPoseInWorld(const sl_projector::Rig& rig, const Eigen::Isometry3d& platform_edge_in_world)
{
  return platform_edge_in_world * toIsometry(rig.mount.cameraOpticalInParent());
}

}  // namespace sl_sim
