// The renderer's kernels, stage 4: the image: storing traced tiles, edges for anti-aliasing, the
// camera blur levels (separable blur, downsampling, row upsampling) and the sensor.
#include "lanes.h"
#include "lanes_common.h"

#include <algorithm>

namespace sl_sim
{
namespace sim
{

SL_SIMD float storeTile(int rows, int cols, const float* __restrict radiance, const float* __restrict t,
                        const int32_t* __restrict obj, const int32_t* __restrict part, const int32_t* __restrict lit,
                        const int32_t* __restrict parity, const float* __restrict u, const float* __restrict v,
                        const float* __restrict cam_sigma, float* __restrict radiance_out, float* __restrict depth_out,
                        float* __restrict coords_out, uint16_t* __restrict keys_out, int stride, int depth_stride,
                        int coords_stride)
{
  // The largest sigma, as the largest bit pattern (sigma >= 0, so the integer order is the float
  // order; an integer maximum vectorises where a float one with NaN semantics does not).
  int32_t max_bits = 0;
  for (int i = 0; i < rows * cols; ++i)
  {
    const int32_t b = __builtin_bit_cast(int32_t, cam_sigma[i]);
    max_bits = b > max_bits ? b : max_bits;
  }
  for (int r = 0; r < rows; ++r)
  {
    const int l = r * cols;
    float* __restrict ro = radiance_out + static_cast<size_t>(r) * stride;
    float* __restrict dout = depth_out + static_cast<size_t>(r) * depth_stride;
    float* __restrict co = coords_out + static_cast<size_t>(r) * coords_stride;
    uint16_t* __restrict ko = keys_out + static_cast<size_t>(r) * stride;
#pragma GCC ivdep
    for (int c = 0; c < cols; ++c)
    {
      const int i = l + c;
      const int o = obj[i];
      ro[c] = radiance[i];
      dout[c] = o >= 0 ? t[i] : kNaN;
      co[2 * c] = u[i];
      co[2 * c + 1] = v[i];
      const int key = (o + 1) | (part[i] << 11) | (lit[i] << 14) | (parity[i] << 15);
      ko[c] = static_cast<uint16_t>(o >= 0 ? key : 0);
    }
  }
  return __builtin_bit_cast(float, max_bits);
}

SL_SIMD void markEdges(const uint16_t* __restrict keys, int w, int h, uint8_t* __restrict edge)
{
  // A pixel is on an edge when any 4-neighbour has another key (rows and columns replicated at the
  // border, so border pixels compare with themselves there).
  for (int y = 0; y < h; ++y)
  {
    const uint16_t* k = keys + static_cast<size_t>(y) * w;
    const uint16_t* up = y > 0 ? k - w : k;
    const uint16_t* down = y + 1 < h ? k + w : k;
    uint8_t* e = edge + static_cast<size_t>(y) * w;
    e[0] = (k[0] != k[1]) | (k[0] != up[0]) | (k[0] != down[0]);
#pragma GCC ivdep
    for (int x = 1; x + 1 < w; ++x)
    {
      const uint16_t c = k[x];
      e[x] = static_cast<uint8_t>((c != k[x - 1]) | (c != k[x + 1]) | (c != up[x]) | (c != down[x]));
    }
    e[w - 1] = (k[w - 1] != k[w - 2]) | (k[w - 1] != up[w - 1]) | (k[w - 1] != down[w - 1]);
  }
}

namespace
{
// One pass of a separable blur. With the radius R known at compile time the taps stay in registers
// (the loop over x vectorises); R = -1 handles any radius r tap by tap, accumulating in `out`.
template <int R>
SL_INLINE void blurRow(const float* __restrict in, float* __restrict out, int width, const float* __restrict w, int r)
{
  if (R >= 0)
  {
#pragma GCC ivdep
    for (int x = 0; x < width; ++x)
    {
      float sum = 0.f;
      for (int j = 0; j <= 2 * R; ++j)
        sum += w[j] * in[x + j];
      out[x] = sum;
    }
    return;
  }
  for (int x = 0; x < width; ++x)
    out[x] = w[0] * in[x];
  for (int j = 1; j <= 2 * r; ++j)
  {
    const float wj = w[j];
    const float* __restrict a = in + j;
#pragma GCC ivdep
    for (int x = 0; x < width; ++x)
      out[x] += wj * a[x];
  }
}

template <int R>
SL_INLINE void blurColumns(const float* const* __restrict rows, float* __restrict out, int width,
                           const float* __restrict w, int r)
{
  if (R >= 0)
  {
#pragma GCC ivdep
    for (int x = 0; x < width; ++x)
    {
      float sum = 0.f;
      for (int j = 0; j <= 2 * R; ++j)
        sum += w[j] * rows[j][x];
      out[x] = sum;
    }
    return;
  }
  const float* __restrict r0 = rows[0];
  for (int x = 0; x < width; ++x)
    out[x] = w[0] * r0[x];
  for (int j = 1; j <= 2 * r; ++j)
  {
    const float wj = w[j];
    const float* __restrict a = rows[j];
#pragma GCC ivdep
    for (int x = 0; x < width; ++x)
      out[x] += wj * a[x];
  }
}

template <int R>
SL_INLINE void blurBody(const float* __restrict src, float* __restrict dst, int width, int height,
                        const float* __restrict w, int r, float* __restrict tmp, float* __restrict row)
{
  for (int y = 0; y < height; ++y)
  {
    const float* in = src + static_cast<size_t>(y) * width;
    for (int x = 0; x < r; ++x)
    {
      row[x] = in[0];
      row[r + width + x] = in[width - 1];
    }
    for (int x = 0; x < width; ++x)
      row[r + x] = in[x];
    blurRow<R>(row, tmp + static_cast<size_t>(y) * width, width, w, r);
  }
  const float* rows[64];
  for (int y = 0; y < height; ++y)
  {
    for (int j = 0; j <= 2 * r; ++j)
      rows[j] = tmp + static_cast<size_t>(std::min(height - 1, std::max(0, y - r + j))) * width;
    blurColumns<R>(rows, dst + static_cast<size_t>(y) * width, width, w, r);
  }
}
}  // namespace

SL_SIMD void blurImage(const float* __restrict src, float* __restrict dst, int width, int height,
                       const float* __restrict w, int r, float* __restrict tmp, float* __restrict row)
{
  switch (r)
  {
    case 1:
      blurBody<1>(src, dst, width, height, w, r, tmp, row);
      break;
    case 2:
      blurBody<2>(src, dst, width, height, w, r, tmp, row);
      break;
    case 3:
      blurBody<3>(src, dst, width, height, w, r, tmp, row);
      break;
    case 8:  // the glare halo at quarter resolution
      blurBody<8>(src, dst, width, height, w, r, tmp, row);
      break;
    default:
      blurBody<-1>(src, dst, width, height, w, r, tmp, row);
      break;
  }
}

SL_SIMD void downsample2(const float* __restrict src, int w, int h, float* __restrict dst, int dw, int dh)
{
  for (int y = 0; y < dh; ++y)
  {
    const float* r0 = src + static_cast<size_t>(std::min(2 * y, h - 1)) * w;
    const float* r1 = src + static_cast<size_t>(std::min(2 * y + 1, h - 1)) * w;
    float* out = dst + static_cast<size_t>(y) * dw;
    for (int x = 0; x < dw; ++x)
    {
      const int x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
      out[x] = 0.25f * (r0[x0] + r0[x1] + r1[x0] + r1[x1]);
    }
  }
}

namespace
{
// Horizontal upsampling of each row by kScale (linear, pixel centres aligned, edges replicated):
// output j of source pixel k lies o = (j + 0.5) / kScale - 0.5 source px from it and blends it with
// its left (o < 0) or right neighbour, weight |o|.
template <int kScale>
SL_INLINE void upsampleRowsBody(const float* __restrict src, int sw, int sh, float* __restrict dst, int dst_stride,
                                float* __restrict pad)
{
  for (int y = 0; y < sh; ++y)
  {
    const float* in = src + static_cast<size_t>(y) * sw;
    pad[0] = in[0];
    for (int x = 0; x < sw; ++x)
      pad[x + 1] = in[x];
    pad[sw + 1] = in[sw - 1];
    float* out = dst + static_cast<size_t>(y) * dst_stride;
#pragma GCC ivdep
    for (int k = 0; k < sw; ++k)
    {
      const float a = pad[k + 1], m = pad[k], p = pad[k + 2];
      for (int j = 0; j < kScale; ++j)
      {
        const float o = (j + 0.5f) / kScale - 0.5f;
        out[kScale * k + j] = o < 0.f ? (1.f + o) * a + -o * m : (1.f - o) * a + o * p;
      }
    }
  }
}
}  // namespace

SL_SIMD void upsampleRows2(const float* __restrict src, int sw, int sh, float* __restrict dst, int dst_stride,
                           float* __restrict pad)
{
  upsampleRowsBody<2>(src, sw, sh, dst, dst_stride, pad);
}

SL_SIMD void upsampleRows4(const float* __restrict src, int sw, int sh, float* __restrict dst, int dst_stride,
                           float* __restrict pad)
{
  upsampleRowsBody<4>(src, sw, sh, dst, dst_stride, pad);
}

SL_SIMD void sensorRow(const KSensor& sensor, const KSensorRow& rows, const float* __restrict depth, int first, int n,
                       float* __restrict scratch, uint8_t* __restrict out)
{
  const KSensor s = sensor;  // local copies: no loads from memory inside the loop
  const KSensorRow r = rows;
  const float* __restrict L0 = s.levels[0];
  const float* __restrict L1 = s.levels[std::min(1, s.n_levels - 1)];
  const float* __restrict L2 = s.levels[std::min(2, s.n_levels - 1)];
  const float* __restrict l3a = r.l3[0];
  const float* __restrict l3b = r.l3[1];
  const float* __restrict l4a = r.l4[0];
  const float* __restrict l4b = r.l4[1];
  const float* __restrict ha = r.halo[0];
  const float* __restrict hb = r.halo[1];
  const float f3 = r.f3, f4 = r.f4, fh = r.fh;
  const float* __restrict vignette = s.vignette;
  const float top =
      s.n_levels >= 5 ? 4.f : (s.n_levels == 4 ? 2.f : (s.n_levels == 3 ? 1.f : (s.n_levels == 2 ? 0.5f : 0.f)));
  const float glare = s.glare;
  const uint32_t ka = s.key_a, kb = s.key_b;
  const float noise = s.noise ? 1.f / 147.8f : 0.f;  // 147.8: standard deviation of a sum of 4 uniform bytes
  const float inv_full_well = s.inv_full_well, read2 = s.read2;
  const float cam_base2 = s.cam_base2, cam_k = s.cam_defocus_k, cam_inv_focus = s.cam_inv_focus;
#pragma GCC ivdep
  for (int k = 0; k < n; ++k)
  {
    const int i = first + k;
    // Camera blur at this pixel's depth (infinity where nothing was hit); piecewise-linear weights
    // ("hats") of the blur levels on their knots 0, 0.5, 1, 2, 4 px.
    const float d = depth[k];
    const float inv_depth = d == d ? 1.f / d : 0.f;
    const float dc = cam_k * std::fabs(inv_depth - cam_inv_focus);
    const float sg = fmin2(std::sqrt(cam_base2 + dc * dc), top);
    const float w0 = fmax2(0.f, 1.f - 2.f * sg);
    const float w1 = fmax2(0.f, fmin2(2.f * sg, 2.f - 2.f * sg));
    const float w2 = fmax2(0.f, fmin2(2.f * sg - 1.f, 2.f - sg));
    const float w3 = fmax2(0.f, fmin2(sg - 1.f, 2.f - 0.5f * sg));
    const float w4 = fmax2(0.f, 0.5f * sg - 1.f);
    const float v3 = l3a[k] + f3 * (l3b[k] - l3a[k]);
    const float v4 = l4a[k] + f4 * (l4b[k] - l4a[k]);
    const float vh = ha[k] + fh * (hb[k] - ha[k]);
    float value = w0 * L0[i] + w1 * L1[i] + w2 * L2[i] + w3 * v3 + w4 * v4;
    value = (1.f - glare) * value + glare * vh;
    value *= vignette[i];
    // Gaussian noise: the sum of the four bytes of a seeded hash of the pixel index (Irwin-Hall).
    uint32_t h = static_cast<uint32_t>(i) ^ ka;
    h ^= h >> 16;
    h *= 0x7feb352dU;
    h ^= h >> 15;
    h *= 0x846ca68bU;
    h ^= h >> 16;
    h += kb;
    h ^= h >> 16;
    h *= 0x7feb352dU;
    h ^= h >> 15;
    h *= 0x846ca68bU;
    h ^= h >> 16;
    const float g =
        static_cast<float>(static_cast<int32_t>((h & 255U) + ((h >> 8) & 255U) + ((h >> 16) & 255U) + (h >> 24)) - 510);
    value += noise * std::sqrt(fmax2(value, 0.f) * inv_full_well + read2) * g;
    // Saturation; 12-bit linear quantisation below (truncating the non-negative value + 0.5).
    scratch[k] = fmin2(fmax2(value * 4095.f + 0.5f, 0.f), 4095.f);
  }
  if (s.lut)
  {
    for (int k = 0; k < n; ++k)
      out[k] = static_cast<uint8_t>(s.lut[static_cast<int>(scratch[k])]);
  }
  else
  {
#pragma GCC ivdep
    for (int k = 0; k < n; ++k)
    {
      const float q = static_cast<float>(static_cast<int32_t>(scratch[k]));
      out[k] = static_cast<uint8_t>(static_cast<int32_t>(q * (255.f / 4095.f) + 0.5f));
    }
  }
}

}  // namespace sim
}  // namespace sl_sim
