// The renderer's kernels, stage 3: the projector side of the hits: projector pixel, irradiance and
// pattern blur, shadow rays, the trilinear pattern lookup, radiance with ambient light and a specular
// lobe.
#include "lanes.h"
#include "lanes_common.h"

namespace sl_sim
{
namespace sim
{

SL_SIMD void projectLanes(const KProjector& projector, const float* __restrict dx, const float* __restrict dy,
                          const float* __restrict t, const int32_t* __restrict obj, const float* __restrict nx,
                          const float* __restrict ny, const float* __restrict nz, int n, float* __restrict u,
                          float* __restrict v, float* __restrict e, float* __restrict level, float* __restrict sx,
                          float* __restrict sy, float* __restrict sz, int32_t* __restrict lit,
                          float* __restrict cam_sigma, float* __restrict proj_depth)
{
  const KProjector p = projector;  // a local copy: no loads from memory inside the loop
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    const bool hit = obj[i] >= 0;
    const float ti = t[i];  // inf where nothing was hit: those lanes are masked below
    const float x_ = dx[i], y_ = dy[i];
    const float px = ti * x_, py = ti * y_, pz = ti;
    const float lx = p.c[0] - px, ly = p.c[1] - py, lz = p.c[2] - pz;  // towards the projector
    const float dist2 = lx * lx + ly * ly + lz * lz;
    const float inv_dist = 1.f / std::sqrt(dist2);
    const float cos_p = (nx[i] * lx + ny[i] * ly + nz[i] * lz) * inv_dist;
    const float qx = p.r[0] * px + p.r[1] * py + p.r[2] * pz + p.tr[0];
    const float qy = p.r[3] * px + p.r[4] * py + p.r[5] * pz + p.tr[1];
    const float qz = p.r[6] * px + p.r[7] * py + p.r[8] * pz + p.tr[2];
    const float iz = 1.f / qz;
    const float xn = qx * iz, yn = qy * iz;
    const float r2 = xn * xn + yn * yn;
    const float radial = 1.f + r2 * (p.k1 + r2 * (p.k2 + r2 * p.k3));
    const float xd = xn * radial + 2.f * p.p1 * xn * yn + p.p2 * (r2 + 2.f * xn * xn);
    const float yd = yn * radial + p.p1 * (r2 + 2.f * yn * yn) + 2.f * p.p2 * xn * yn;
    const float uu = p.fx * xd + p.cx, vv = p.fy * yd + p.cy;
    const bool ok = hit & (cos_p > 0.f) & (qz > 0.f) & (uu >= -0.5f) & (vv >= -0.5f) & (uu < p.umax) & (vv < p.vmax);
    const float fu = uu - p.frame_cx, fv = vv - p.frame_cy;
    const float fall = 1.f - p.falloff * (fu * fu + fv * fv) * p.inv_half_diag2;
    // falloff_weight 1, flat_power 0: the physical P cos / d^2; 0 and the power: no falloff. A blend,
    // not a branch, so that the loop still vectorises.
    const float irradiance = (p.power_focus2 * cos_p / dist2 * p.falloff_weight + p.flat_power) * fall;
    // Blur of the pattern on the surface, projector px^2: base, defocus, the camera pixel's
    // footprint (a box of fp projector px: fp^2 / 12) and the mirror's own box (1/12), less what
    // bilinear interpolation adds (1/6).
    const float dn = std::sqrt(x_ * x_ + y_ * y_ + 1.f);
    const float cos_c = fmax2(-(nx[i] * x_ + ny[i] * y_ + nz[i]) / dn, 0.05f);
    const float fp = ti * dn * p.footprint_k * inv_dist * std::sqrt(fmax2(cos_p, 0.f) / cos_c);
    const float dfc = p.defocus_k * std::fabs(iz - p.inv_focus);
    const float s2 = p.base2 + dfc * dfc + fp * fp * (1.f / 12.f) - 1.f / 12.f;
    const float s = std::sqrt(fmax2(s2, 1e-12f));
    const float lv = s <= p.sigma1 ? s / p.sigma1 : fmin2(p.max_level, 1.f + 2.f * log2Approx(s / p.sigma1));
    const float inv_depth = 1.f / ti;  // 0 where nothing was hit (t = inf)
    const float dc = p.cam_defocus_k * std::fabs(inv_depth - p.cam_inv_focus);
    u[i] = ok ? uu : kNaN;
    v[i] = ok ? vv : kNaN;
    e[i] = ok ? irradiance : 0.f;
    level[i] = ok ? lv : 0.f;
    sx[i] = -lx;
    sy[i] = -ly;
    sz[i] = -lz;
    lit[i] = ok ? 1 : 0;
    cam_sigma[i] = std::sqrt(p.cam_base2 + dc * dc);
    proj_depth[i] = ok ? qz : 0.f;
  }
}

SL_SIMD bool litBounds(const float* __restrict u, const float* __restrict v, const int32_t* __restrict lit,
                       const float* __restrict proj_depth, int n, float* box)
{
  // Lit lanes have u, v >= -0.5 and depth > 0: shifted by 0.5 they are non-negative, so integer
  // comparisons of their bit patterns order them (and vectorise).
  int32_t umin = 0x7f7fffff, umax = 0, vmin = 0x7f7fffff, vmax = 0, dmax = 0, any = 0;
  for (int i = 0; i < n; ++i)
  {
    const bool l = lit[i] != 0;
    const int32_t ub = __builtin_bit_cast(int32_t, u[i] + 0.5f), vb = __builtin_bit_cast(int32_t, v[i] + 0.5f);
    const int32_t db = __builtin_bit_cast(int32_t, proj_depth[i]);
    const int32_t un = l ? ub : 0x7f7fffff, ux = l ? ub : 0, vn = l ? vb : 0x7f7fffff, vx = l ? vb : 0;
    umin = un < umin ? un : umin;
    umax = ux > umax ? ux : umax;
    vmin = vn < vmin ? vn : vmin;
    vmax = vx > vmax ? vx : vmax;
    dmax = db > dmax ? db : dmax;
    any |= lit[i];
  }
  box[0] = __builtin_bit_cast(float, umin) - 0.5f;
  box[1] = __builtin_bit_cast(float, umax) - 0.5f;
  box[2] = __builtin_bit_cast(float, vmin) - 0.5f;
  box[3] = __builtin_bit_cast(float, vmax) - 0.5f;
  box[4] = __builtin_bit_cast(float, dmax);
  return any != 0;
}

namespace
{
// Kernels that need gathers: the compiler does not vectorise those for generic x86-64 tuning, so
// an AVX2 version is written out and chosen at run time; the portable loop is the reference.
// Pattern levels are packed: each 32-bit entry holds the value at (x, y) in its low 16 bits and at
// (x + 1, y) in its high 16 bits (0..65535), so that one gather fetches both horizontal neighbours.
constexpr float kPatternScale = 1.f / 65535.f;

SL_INLINE float bilinearPacked(const uint32_t* p, int stride, float fx, float fy)
{
  const uint32_t top = p[0], bottom = p[stride];
  const float a0 = static_cast<float>(top & 0xffffU), a1 = static_cast<float>(top >> 16);
  const float a2 = static_cast<float>(bottom & 0xffffU), a3 = static_cast<float>(bottom >> 16);
  const float t = a0 + fx * (a1 - a0), b = a2 + fx * (a3 - a2);
  return (t + fy * (b - t)) * kPatternScale;
}

void patternScalar(const uint32_t* levels, int level_size, int stride, int pad, const float* u, const float* v,
                   const float* level, const int32_t* lit, int n, float* value)
{
  const float fpad = static_cast<float>(pad);
  for (int i = 0; i < n; ++i)
  {
    if (!lit[i])
    {
      value[i] = 0.f;
      continue;
    }
    const float gx = u[i] + fpad, gy = v[i] + fpad, lv = level[i];
    const int x0 = static_cast<int>(gx), y0 = static_cast<int>(gy), l0 = static_cast<int>(lv);
    const float fx = gx - static_cast<float>(x0), fy = gy - static_cast<float>(y0), fl = lv - static_cast<float>(l0);
    const uint32_t* p = levels + l0 * level_size + y0 * stride + x0;
    const float v0 = bilinearPacked(p, stride, fx, fy);
    const float v1 = bilinearPacked(p + level_size, stride, fx, fy);  // a spare zero level follows the last
    value[i] = v0 + fl * (v1 - v0);
  }
}

#ifdef SL_HAVE_AVX2_KERNELS
__attribute__((target("avx2,fma"), always_inline)) inline __m256 bilinearPackedAvx2(const uint32_t* levels, __m256i b,
                                                                                    __m256i vstride, __m256 fx,
                                                                                    __m256 fy)
{
  const __m256i low = _mm256_set1_epi32(0xffff);
  const int* base = reinterpret_cast<const int*>(levels);
  const __m256i top = _mm256_i32gather_epi32(base, b, 4);
  const __m256i bottom = _mm256_i32gather_epi32(base, _mm256_add_epi32(b, vstride), 4);
  const __m256 a0 = _mm256_cvtepi32_ps(_mm256_and_si256(top, low));
  const __m256 a1 = _mm256_cvtepi32_ps(_mm256_srli_epi32(top, 16));
  const __m256 a2 = _mm256_cvtepi32_ps(_mm256_and_si256(bottom, low));
  const __m256 a3 = _mm256_cvtepi32_ps(_mm256_srli_epi32(bottom, 16));
  const __m256 t = _mm256_fmadd_ps(fx, _mm256_sub_ps(a1, a0), a0);
  const __m256 bt = _mm256_fmadd_ps(fx, _mm256_sub_ps(a3, a2), a2);
  return _mm256_fmadd_ps(fy, _mm256_sub_ps(bt, t), t);
}

__attribute__((target("avx2,fma"))) void patternAvx2(const uint32_t* levels, int level_size, int stride, int pad,
                                                     const float* u, const float* v, const float* level,
                                                     const int32_t* lit, int n, float* value)
{
  const __m256 fpad = _mm256_set1_ps(static_cast<float>(pad)), scale = _mm256_set1_ps(kPatternScale);
  const __m256i vsize = _mm256_set1_epi32(level_size), vstride = _mm256_set1_epi32(stride);
  for (int i = 0; i + 8 <= n; i += 8)
  {
    const __m256i l = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(lit + i));
    const __m256 ok = _mm256_castsi256_ps(_mm256_cmpgt_epi32(l, _mm256_setzero_si256()));
    if (_mm256_movemask_ps(ok) == 0)
    {
      _mm256_storeu_ps(value + i, _mm256_setzero_ps());
      continue;
    }
    // Unlit lanes read the frame's corner of level 0 (their u, v may be NaN).
    const __m256 gx = _mm256_blendv_ps(fpad, _mm256_add_ps(_mm256_loadu_ps(u + i), fpad), ok);
    const __m256 gy = _mm256_blendv_ps(fpad, _mm256_add_ps(_mm256_loadu_ps(v + i), fpad), ok);
    const __m256 lv = _mm256_blendv_ps(_mm256_setzero_ps(), _mm256_loadu_ps(level + i), ok);
    const __m256i x0 = _mm256_cvttps_epi32(gx), y0 = _mm256_cvttps_epi32(gy), l0 = _mm256_cvttps_epi32(lv);
    const __m256 fx = _mm256_sub_ps(gx, _mm256_cvtepi32_ps(x0));
    const __m256 fy = _mm256_sub_ps(gy, _mm256_cvtepi32_ps(y0));
    const __m256 fl = _mm256_sub_ps(lv, _mm256_cvtepi32_ps(l0));
    const __m256i b0 =
        _mm256_add_epi32(_mm256_add_epi32(_mm256_mullo_epi32(l0, vsize), _mm256_mullo_epi32(y0, vstride)), x0);
    const __m256 v0 = bilinearPackedAvx2(levels, b0, vstride, fx, fy);
    const __m256 v1 = bilinearPackedAvx2(levels, _mm256_add_epi32(b0, vsize), vstride, fx, fy);
    const __m256 r = _mm256_mul_ps(_mm256_fmadd_ps(fl, _mm256_sub_ps(v1, v0), v0), scale);
    _mm256_storeu_ps(value + i, _mm256_and_ps(r, ok));
  }
}
#endif
}  // namespace

void patternLanes(const uint32_t* levels, int level_size, int stride, int pad, const float* u, const float* v,
                  const float* level, const int32_t* lit, int n, float* value)
{
#ifdef SL_HAVE_AVX2_KERNELS
  if (haveAvx2() && n % 8 == 0)
  {
    patternAvx2(levels, level_size, stride, pad, u, v, level, lit, n, value);
    return;
  }
#endif
  patternScalar(levels, level_size, stride, pad, u, v, level, lit, n, value);
}

SL_SIMD void shadowLanes(const float* __restrict tsh, float t_max, int n, int32_t* __restrict lit, float* __restrict u,
                         float* __restrict v)
{
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    const bool shadowed = tsh[i] < t_max;
    const int32_t l = lit[i];
    const float uu = u[i], vv = v[i];
    lit[i] = shadowed ? 0 : l;
    u[i] = shadowed ? kNaN : uu;
    v[i] = shadowed ? kNaN : vv;
  }
}

SL_SIMD void radianceLanes(float ambient, float black, const float* __restrict albedo, const float* __restrict e,
                           const float* __restrict pattern, const int32_t* __restrict lit, int n,
                           float* __restrict direct, float* __restrict radiance)
{
  const float gain = 1.f - black;
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    const float d = lit[i] ? e[i] * (black + gain * pattern[i]) : 0.f;
    direct[i] = d;
    radiance[i] = albedo[i] * (ambient + d);
  }
}

SL_SIMD void specularLanes(int id, float ks_norm, float shininess, const float* __restrict dx,
                           const float* __restrict dy, const float* __restrict sx, const float* __restrict sy,
                           const float* __restrict sz, const float* __restrict nx, const float* __restrict ny,
                           const float* __restrict nz, const int32_t* __restrict obj, const float* __restrict direct,
                           int n, float* __restrict radiance)
{
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    // Half vector of the direction to the projector (-s) and to the camera (-d).
    const float is = 1.f / std::sqrt(sx[i] * sx[i] + sy[i] * sy[i] + sz[i] * sz[i]);
    const float id_ = 1.f / std::sqrt(dx[i] * dx[i] + dy[i] * dy[i] + 1.f);
    const float hx = -sx[i] * is - dx[i] * id_, hy = -sy[i] * is - dy[i] * id_, hz = -sz[i] * is - id_;
    const float ih = 1.f / std::sqrt(fmax2(hx * hx + hy * hy + hz * hz, 1e-20f));
    const float nh = (nx[i] * hx + ny[i] * hy + nz[i] * hz) * ih;
    const float lobe = exp2Approx(shininess * log2Approx(fmax2(nh, 1e-20f)));
    const bool m = (obj[i] == id) & (nh > 0.f) & (direct[i] > 0.f);
    radiance[i] += m ? ks_norm * lobe * direct[i] : 0.f;
  }
}

}  // namespace sim
}  // namespace sl_sim
