// The renderer's set-up: camera rays and tiles, projector optics, the vignetting, output and
// texture tables, the frame buffers, blur kernels and anti-aliasing rays; and the pattern pyramid,
// rebuilt when the projector frame changes. See renderer.cpp for the stages.
#include "renderer_impl.h"

#include <cstring>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace sl_sim
{
// The renderer's internal types, constants and kernels.
using namespace sim;

namespace
{
// The frustum of four corner rays r00, r10, r01, r11 from an apex.
Frustum makeFrustum(const Eigen::Vector3d& apex, const Eigen::Vector3d& axis, const Eigen::Vector3d& r00,
                    const Eigen::Vector3d& r10, const Eigen::Vector3d& r01, const Eigen::Vector3d& r11)
{
  const Eigen::Vector3d centre = r00.normalized() + r10.normalized() + r01.normalized() + r11.normalized();
  const std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 4> edges = {
    { { r00, r01 }, { r00, r10 }, { r10, r11 }, { r01, r11 } }
  };
  Frustum f;
  for (int i = 0; i < 4; ++i)
  {
    Eigen::Vector3d n = edges[static_cast<size_t>(i)].first.cross(edges[static_cast<size_t>(i)].second).normalized();
    if (n.dot(centre) < 0.0)
      n = -n;
    f.n[static_cast<size_t>(i)] = n.cast<float>();
    f.d[static_cast<size_t>(i)] = static_cast<float>(n.dot(apex));
  }
  f.corner = { r00.cast<float>(), r10.cast<float>(), r01.cast<float>(), r11.cast<float>() };
  f.apex = apex.cast<float>();
  f.axis = axis.cast<float>();
  return f;
}
}  // namespace

Renderer::Impl::Impl(const sl_projector::Rig& r, const SimSettings& s) : rig(r), settings(s)
{
  settings.validate();
  try
  {
    rig.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("rig: ") + e.what());
  }
  // The lenses are the rig's unless a setting overrides them (settings() reports the values used).
  auto orRig = [](double& setting, double rig_value) { setting = setting > 0.0 ? setting : rig_value; };
  orRig(settings.projector_focus_distance, rig.projector_optics.focus_distance);
  orRig(settings.projector_f_number, rig.projector_optics.f_number);
  orRig(settings.projector_pixel_size, rig.projector_optics.pixel_pitch);
  orRig(settings.camera_focus_distance, rig.camera_optics.focus_distance);
  orRig(settings.camera_f_number, rig.camera_optics.f_number);
  orRig(settings.camera_pixel_size, rig.camera_optics.pixel_pitch);
  W = rig.camera.width;
  H = rig.camera.height;
  Wp = rig.projector.width;
  Hp = rig.projector.height;
  buildCamera();
  buildProjector();
  buildTables();
  allocateFrameBuffers();
  makeCameraBlurKernels();
  makeAntialiasRays();
}

void Renderer::Impl::allocateFrameBuffers()
{
  lanes.reset(new Lanes());
  segments.reserve(kLanes);
  std::fill(std::begin(lanes->ones), std::end(lanes->ones), 1.f);
  std::fill(std::begin(lanes->none), std::end(lanes->none), -1);
  const size_t n = static_cast<size_t>(W) * H;
  keys.assign(n, 0);
  edge.assign(n, 0);
  edge_pixels.reserve(n);
  levels.assign(n * kCameraLevels, 0.f);
  hw = (W + 1) / 2;
  hh = (H + 1) / 2;
  qw = (hw + 1) / 2;
  qh = (hh + 1) / 2;
  half_in.assign(static_cast<size_t>(hw) * hh, 0.f);
  half_blur.assign(half_in.size(), 0.f);
  quarter_in.assign(static_cast<size_t>(qw) * qh, 0.f);
  quarter_blur.assign(quarter_in.size(), 0.f);
  quarter_halo.assign(quarter_in.size(), 0.f);
  tmp.assign(n, 0.f);
  row.assign(static_cast<size_t>(W + 256), 0.f);
  up_half.make(H, hh, 2);
  up_quarter.make(H, qh, 4);
  row_stride = 4 * qw;  // >= 2 hw >= W
  rows_half.assign(static_cast<size_t>(hh) * row_stride, 0.f);
  rows_quarter.assign(static_cast<size_t>(qh) * row_stride, 0.f);
  rows_halo.assign(static_cast<size_t>(qh) * row_stride, 0.f);
}

void Renderer::Impl::makeCameraBlurKernels()
{
  // Incremental blurs (variances add): 0 -> 0.5 -> 1 px at full resolution; to 2 px at half
  // resolution after a 2 x 2 box (1/3 px^2) and before bilinear upsampling (2/3 px^2); to 4 px at
  // quarter resolution likewise (box 4/3, upsampling 8/3 full px^2). Kernel sigmas in the
  // resolution they run at.
  k1.make(0.5f);
  k2.make(std::sqrt(1.f - 0.25f));
  k3.make(std::sqrt(4.f - 1.f - 1.f / 3.f - 2.f / 3.f) / 2.f);
  k4.make(std::sqrt(16.f - (4.f - 2.f / 3.f) - 4.f / 3.f - 8.f / 3.f) / 4.f);
  kglare.make(std::sqrt(kGlareSigma * kGlareSigma - (4.f - 2.f / 3.f) - 4.f / 3.f - 8.f / 3.f) / 4.f);
}

void Renderer::Impl::makeAntialiasRays()
{
  if (settings.antialias == 4)
  {
    // The centre sample and three more on a circle of 0.4 px, 120 degrees apart (rotated off the
    // pixel axes): four samples for three new rays.
    aa_with_centre = true;
    for (int k = 0; k < 3; ++k)
    {
      const float a = static_cast<float>((15.0 + 120.0 * k) * M_PI / 180.0);
      aa_offsets.push_back({ 0.4f * std::cos(a), 0.4f * std::sin(a) });
    }
  }
  else if (settings.antialias == 16)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i)
        aa_offsets.push_back({ (i + 0.5f) / 4.f - 0.5f, (j + 0.5f) / 4.f - 0.5f });
  for (const auto& off : aa_offsets)
  {
    const int ix = off[0] < 0.f ? -1 : 0, iy = off[1] < 0.f ? -1 : 0;
    const float fx = off[0] - ix, fy = off[1] - iy;
    aa_rays.push_back({ static_cast<std::ptrdiff_t>(iy) * grid_w + ix,
                        { (1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy } });
  }
}

void Renderer::Impl::buildCamera()
{
  grid_w = W + 2;
  ray_x.resize(static_cast<size_t>(grid_w) * (H + 2));
  ray_y.resize(ray_x.size());
  for (int v = -1; v <= H; ++v)
    for (int u = -1; u <= W; ++u)
    {
      const Eigen::Vector3d r = rig.camera.ray(Eigen::Vector2d(u, v));
      const size_t i = static_cast<size_t>(v + 1) * grid_w + (u + 1);
      ray_x[i] = static_cast<float>(r.x());
      ray_y[i] = static_cast<float>(r.y());
    }
  const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile;
  tile_dx.assign(static_cast<size_t>(tiles_x) * tiles_y * kLanes, 0.f);
  tile_dy.assign(tile_dx.size(), 0.f);
  for (int ty = 0; ty < tiles_y; ++ty)
    for (int tx = 0; tx < tiles_x; ++tx)
    {
      const int x0 = tx * kTile, y0 = ty * kTile;
      const int tw = std::min(kTile, W - x0), th = std::min(kTile, H - y0);
      float* dx = tile_dx.data() + static_cast<size_t>(ty * tiles_x + tx) * kLanes;
      float* dy = tile_dy.data() + static_cast<size_t>(ty * tiles_x + tx) * kLanes;
      for (int i = 0; i < kLanes; ++i)
      {
        const int k = i < tw * th ? i : 0;
        const size_t g = static_cast<size_t>(y0 + k / tw + 1) * grid_w + (x0 + k % tw + 1);
        dx[i] = ray_x[g];
        dy[i] = ray_y[g];
      }
    }
  // Tiles padded by one pixel: anti-aliasing rays stay within +-0.5 px of their pixel.
  makeTiles(
      cam_tiles, W, H, 1.0, [this](double u, double v) { return rig.camera.ray(Eigen::Vector2d(u, v)); },
      Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
}

void Renderer::Impl::buildProjector()
{
  const SimSettings& s = settings;
  const Eigen::Matrix3d R = rig.projector_pose.rotation;
  const Eigen::Vector3d t = rig.projector_pose.translation;
  const Eigen::Matrix3d Rt = R.transpose();
  const Eigen::Vector3d tt = -(Rt * t);
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      kp.r[3 * r + c] = static_cast<float>(Rt(r, c));
    kp.tr[r] = static_cast<float>(tt[r]);
    kp.c[r] = static_cast<float>(t[r]);
  }
  Cp = t.cast<float>();
  const sl_projector::PinholeModel& P = rig.projector;
  kp.fx = static_cast<float>(P.fx);
  kp.fy = static_cast<float>(P.fy);
  kp.cx = static_cast<float>(P.cx);
  kp.cy = static_cast<float>(P.cy);
  kp.k1 = static_cast<float>(P.dist[0]);
  kp.k2 = static_cast<float>(P.dist[1]);
  kp.p1 = static_cast<float>(P.dist[2]);
  kp.p2 = static_cast<float>(P.dist[3]);
  kp.k3 = static_cast<float>(P.dist[4]);
  kp.umax = Wp - 0.5f;
  kp.vmax = Hp - 0.5f;
  kp.frame_cx = (Wp - 1) / 2.f;
  kp.frame_cy = (Hp - 1) / 2.f;
  kp.inv_half_diag2 = 1.f / (kp.frame_cx * kp.frame_cx + kp.frame_cy * kp.frame_cy + 1e-6f);
  kp.falloff = static_cast<float>(1.0 - s.projector_vignetting);
  kp.power_focus2 = static_cast<float>(s.projector_power * s.projector_focus_distance * s.projector_focus_distance);
  kp.falloff_weight = s.irradiance_falloff ? 1.f : 0.f;
  kp.flat_power = s.irradiance_falloff ? 0.f : static_cast<float>(s.projector_power);
  // Thin lens (sl_projector::LensOptics, the settings' lens, the rig's where a setting is 0); a disc
  // of diameter b has the second moment of a Gaussian of sigma b / 4.
  auto defocusK = [&s](double f_px, double pitch, double n, double focus)
  {
    const sl_projector::LensOptics lens{ focus, n, pitch };
    return s.defocus_scale * lens.defocusPerInverseDepth(f_px) / 4.0;
  };
  const double pf = std::sqrt(P.fx * P.fy);
  const double cf = std::sqrt(rig.camera.fx * rig.camera.fy);
  proj_defocus_k =
      s.defocus ? defocusK(pf, s.projector_pixel_size, s.projector_f_number, s.projector_focus_distance) : 0.0;
  cam_defocus_k = s.defocus ? defocusK(cf, s.camera_pixel_size, s.camera_f_number, s.camera_focus_distance) : 0.0;
  kp.defocus_k = static_cast<float>(proj_defocus_k);
  kp.inv_focus = static_cast<float>(1.0 / s.projector_focus_distance);
  kp.base2 = static_cast<float>(s.projector_base_blur * s.projector_base_blur);
  kp.footprint_k = static_cast<float>(pf / cf);
  kp.cam_defocus_k = static_cast<float>(cam_defocus_k);
  kp.cam_inv_focus = static_cast<float>(1.0 / s.camera_focus_distance);
  kp.cam_base2 = static_cast<float>(s.camera_base_blur * s.camera_base_blur);
  kp.sigma1 = kPatternSigma1;
  kp.max_level = static_cast<float>(kPatternLevels - 1);
  ambient = static_cast<float>(s.ambient);
  black = static_cast<float>(s.projector_black_level);
  makeTiles(
      proj_tiles, Wp, Hp, 0.5,
      [this, R](double u, double v) { return Eigen::Vector3d(R * rig.projector.ray(Eigen::Vector2d(u, v))); }, t,
      R.col(2));
}

template <typename RayFn>
void Renderer::Impl::makeTiles(TileLists& tl, int width, int height, double pad, RayFn ray, const Eigen::Vector3d& apex,
                               const Eigen::Vector3d& axis)
{
  tl.nx = (width + kTile - 1) / kTile;
  tl.ny = (height + kTile - 1) / kTile;
  tl.cnx = (tl.nx + kCoarse - 1) / kCoarse;
  tl.cny = (tl.ny + kCoarse - 1) / kCoarse;
  auto frustum = [&](int x0, int y0, int x1, int y1) {  // pixel range, inclusive
    const double a = x0 - 0.5 - pad, b = x1 + 0.5 + pad, c = y0 - 0.5 - pad, d = y1 + 0.5 + pad;
    return makeFrustum(apex, axis, ray(a, c), ray(b, c), ray(a, d), ray(b, d));
  };
  for (int ty = 0; ty < tl.ny; ++ty)
    for (int tx = 0; tx < tl.nx; ++tx)
      tl.fine.push_back(frustum(tx * kTile, ty * kTile, std::min(width, (tx + 1) * kTile) - 1,
                                std::min(height, (ty + 1) * kTile) - 1));
  const int ck = kTile * kCoarse;
  for (int ty = 0; ty < tl.cny; ++ty)
    for (int tx = 0; tx < tl.cnx; ++tx)
      tl.coarse.push_back(
          frustum(tx * ck, ty * ck, std::min(width, (tx + 1) * ck) - 1, std::min(height, (ty + 1) * ck) - 1));
  tl.counts.assign(tl.fine.size(), 0);
  tl.coarse_counts.assign(tl.coarse.size(), 0);
}

void Renderer::Impl::buildTables()
{
  const SimSettings& s = settings;
  // Vignetting: 1 at the principal point, falling quadratically with the radius to `vignetting`
  // at the farthest image corner; the exposure folded in.
  vignette.resize(static_cast<size_t>(W) * H);
  const double cx = rig.camera.cx, cy = rig.camera.cy;
  double r2max = 0.0;
  for (double u : { -0.5, W - 0.5 })
    for (double v : { -0.5, H - 0.5 })
      r2max = std::max(r2max, (u - cx) * (u - cx) + (v - cy) * (v - cy));
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u)
    {
      const double r2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / r2max;
      vignette[static_cast<size_t>(v) * W + u] = static_cast<float>(s.exposure * (1.0 - (1.0 - s.vignetting) * r2));
    }
  // Output curve: 12-bit linear signal to 8 bits with gamma.
  lut.resize(kLutSize);
  for (int i = 0; i < kLutSize; ++i)
  {
    const double x = static_cast<double>(i) / (kLutSize - 1);
    lut[static_cast<size_t>(i)] =
        static_cast<int32_t>(std::min(255.0, std::floor(255.0 * std::pow(x, 1.0 / s.gamma) + 0.5)));
  }
  // Tileable fractal value noise: octaves of smoothstep-interpolated lattice noise, periods 16, 8,
  // 4 texels (a `scale` is 16 texels).
  texture.assign(static_cast<size_t>(kTextureSize) * kTextureSize, 0.f);
  float amplitude = 1.f;
  for (int period = 16; period >= 4; period /= 2)
  {
    const int cells = kTextureSize / period;
    auto lattice = [&](int i, int j)
    {
      const uint32_t h = hash32(static_cast<uint32_t>(((i % cells) * 7919 + (j % cells)) * 31 + period));
      return static_cast<float>(h >> 8) / 16777216.f;
    };
    for (int y = 0; y < kTextureSize; ++y)
      for (int x = 0; x < kTextureSize; ++x)
      {
        const int cx0 = x / period, cy0 = y / period;
        float fx = static_cast<float>(x % period) / period, fy = static_cast<float>(y % period) / period;
        fx = fx * fx * (3.f - 2.f * fx);
        fy = fy * fy * (3.f - 2.f * fy);
        const float a = lattice(cx0, cy0), b = lattice(cx0 + 1, cy0), c = lattice(cx0, cy0 + 1),
                    d = lattice(cx0 + 1, cy0 + 1);
        texture[static_cast<size_t>(y) * kTextureSize + x] +=
            amplitude * ((a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy);
      }
    amplitude *= 0.5f;
  }
  const auto range = std::minmax_element(texture.begin(), texture.end());
  const float lo = *range.first, hi = *range.second;
  for (float& v : texture)
    v = (v - lo) / std::max(hi - lo, 1e-6f);
}

void Renderer::Impl::updatePattern(const cv::Mat& pattern)
{
  if (pattern.empty() || pattern.type() != CV_8UC1 || pattern.cols != Wp || pattern.rows != Hp)
    throw std::invalid_argument("pattern: must be a CV_8UC1 image of the projector's " + std::to_string(Wp) + " x " +
                                std::to_string(Hp) + " px, got " + std::to_string(pattern.cols) + " x " +
                                std::to_string(pattern.rows) + " of OpenCV type " + std::to_string(pattern.type()));
  bool same = !pattern_copy.empty();
  for (int y = 0; same && y < Hp; ++y)
    same = std::memcmp(pattern.ptr<uint8_t>(y), pattern_copy.ptr<uint8_t>(y), static_cast<size_t>(Wp)) == 0;
  if (same)
    return;
  pattern.copyTo(pattern_copy);
  cv::Mat base;
  pattern.convertTo(base, CV_32F, 1.0 / 255.0);
  level_w = Wp + 2 * kPatternPad;
  level_h = Hp + 2 * kPatternPad;
  level_size = level_w * level_h;
  // A spare zero level after the last one: trilinear reads stay inside the buffer.
  pattern_levels.assign(static_cast<size_t>(level_size) * (kPatternLevels + 1), 0u);
  cv::Mat level(level_h, level_w, CV_32F);
  for (int k = 0; k < kPatternLevels; ++k)
  {
    cv::Mat blurred;
    if (k == 0)
      blurred = base;
    else
    {
      const double s = kPatternSigma1 * std::pow(std::sqrt(2.0), k - 1);
      cv::GaussianBlur(base, blurred, cv::Size(0, 0), s, s, cv::BORDER_CONSTANT);
    }
    level.setTo(0.f);
    blurred.copyTo(level(cv::Rect(kPatternPad, kPatternPad, Wp, Hp)));
    uint32_t* packed = pattern_levels.data() + static_cast<size_t>(k) * level_size;
    for (int y = 0; y < level_h; ++y)
      for (int x = 0; x < level_w; ++x)
      {
        auto q = [&](int xx)
        {
          const float v = xx < level_w ? level.at<float>(y, xx) : 0.f;
          return static_cast<uint32_t>(std::min(std::max(v, 0.f), 1.f) * 65535.f + 0.5f);
        };
        packed[static_cast<size_t>(y) * level_w + x] = q(x) | (q(x + 1) << 16);
      }
  }
}

}  // namespace sl_sim
