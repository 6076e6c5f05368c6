// The renderer, stages 4 and 5: camera defocus (blur levels of the radiance image blended per pixel
// by depth), glare halo; then the sensor: vignetting, exposure, noise, quantisation, output curve.
#include "renderer_impl.h"

namespace sl_sim
{
// The renderer's internal types, constants and kernels.
using namespace sim;

namespace
{
// 64-bit mixing (the user's seed -> frame keys).
inline uint64_t mix64(uint64_t z)
{
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

int Renderer::Impl::cameraLevelsNeeded() const
{
  int n = 1;
  while (n < kCameraLevels && kCameraTopSigma[n - 1] < max_sigma)
    ++n;
  return n;
}

// Camera blur levels: 1 and 2 at full resolution, 3 (2 px) at half, 4 (4 px) and the glare halo
// at quarter resolution, their rows upsampled horizontally (the sensor interpolates vertically).
void Renderer::Impl::blurCamera(int n_levels, bool need_glare)
{
  if (need_glare)
    n_levels = kCameraLevels;
  if (n_levels > 1)
    sim::blurImage(level(0), level(1), W, H, k1.w.data(), k1.radius, tmp.data(), row.data());
  if (n_levels > 2)
    sim::blurImage(level(1), level(2), W, H, k2.w.data(), k2.radius, tmp.data(), row.data());
  if (n_levels > 3)
  {
    sim::downsample2(level(2), W, H, half_in.data(), hw, hh);
    sim::blurImage(half_in.data(), half_blur.data(), hw, hh, k3.w.data(), k3.radius, tmp.data(), row.data());
    sim::upsampleRows2(half_blur.data(), hw, hh, rows_half.data(), row_stride, row.data());
  }
  if (n_levels > 4)
  {
    sim::downsample2(half_blur.data(), hw, hh, quarter_in.data(), qw, qh);
    sim::blurImage(quarter_in.data(), quarter_blur.data(), qw, qh, k4.w.data(), k4.radius, tmp.data(), row.data());
    sim::upsampleRows4(quarter_blur.data(), qw, qh, rows_quarter.data(), row_stride, row.data());
  }
  if (need_glare)
  {
    sim::blurImage(quarter_in.data(), quarter_halo.data(), qw, qh, kglare.w.data(), kglare.radius, tmp.data(),
                   row.data());
    sim::upsampleRows4(quarter_halo.data(), qw, qh, rows_halo.data(), row_stride, row.data());
  }
}

void Renderer::Impl::sensor(uint64_t seed, const cv::Mat& depth, cv::Mat& image)
{
  const int n_levels = cameraLevelsNeeded();
  const bool glare = settings.glare > 0.0;
  blurCamera(n_levels, glare);
  sim::KSensor s;
  for (int k = 0; k < 3; ++k)
    s.levels[k] = level(k);
  s.n_levels = n_levels;
  s.glare = glare ? static_cast<float>(settings.glare) : 0.f;
  s.vignette = vignette.data();
  s.lut = settings.gamma == 1.0 ? nullptr : lut.data();
  s.cam_base2 = kp.cam_base2;
  s.cam_defocus_k = kp.cam_defocus_k;
  s.cam_inv_focus = kp.cam_inv_focus;
  s.noise = settings.noise;
  s.inv_full_well = static_cast<float>(1.0 / settings.full_well);
  const float read = static_cast<float>(settings.read_noise / 255.0);
  s.read2 = read * read;
  const uint64_t k = mix64(seed);
  s.key_a = static_cast<uint32_t>(k);
  s.key_b = static_cast<uint32_t>(k >> 32);
  // Rows not computed this frame have weight 0; any valid row will do.
  const float* fallback = level(0);
  for (int v = 0; v < H; ++v)
  {
    sim::KSensorRow r;
    const size_t yh = static_cast<size_t>(up_half.y0[static_cast<size_t>(v)]);
    const size_t yq = static_cast<size_t>(up_quarter.y0[static_cast<size_t>(v)]);
    const size_t yh1 = std::min(yh + 1, static_cast<size_t>(hh - 1)),
                 yq1 = std::min(yq + 1, static_cast<size_t>(qh - 1));
    const bool has3 = n_levels > 3, has4 = n_levels > 4;
    r.l3[0] = has3 ? rows_half.data() + yh * row_stride : fallback;
    r.l3[1] = has3 ? rows_half.data() + yh1 * row_stride : fallback;
    r.f3 = up_half.fy[static_cast<size_t>(v)];
    r.l4[0] = has4 ? rows_quarter.data() + yq * row_stride : fallback;
    r.l4[1] = has4 ? rows_quarter.data() + yq1 * row_stride : fallback;
    r.f4 = up_quarter.fy[static_cast<size_t>(v)];
    r.halo[0] = glare ? rows_halo.data() + yq * row_stride : fallback;
    r.halo[1] = glare ? rows_halo.data() + yq1 * row_stride : fallback;
    r.fh = r.f4;
    sim::sensorRow(s, r, depth.ptr<float>(v), v * W, W, row.data(), image.ptr<uint8_t>(v));
  }
}

}  // namespace sl_sim
