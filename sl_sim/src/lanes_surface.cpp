// The renderer's kernels, stage 2: surfaces at the hits: normal, albedo, texture (checker, noise,
// checkerboard). Type 0 plane, 1 box, 2 cylinder; Tex 0 none, 1 checker, 2 noise, 3 checkerboard.
#include "lanes.h"
#include "lanes_common.h"

namespace sl_sim
{
namespace sim
{

namespace
{
template <int kType, int kTex>
SL_INLINE void surfaceBody(const KSurface& surface, const float* __restrict dx, const float* __restrict dy,
                           const float* __restrict t, const int32_t* __restrict obj, const int32_t* __restrict part,
                           int n, float* __restrict nx, float* __restrict ny, float* __restrict nz,
                           float* __restrict albedo, int32_t* __restrict parity, float* __restrict tu,
                           float* __restrict tv)
{
  const KSurface s = surface;  // a local copy: no loads from memory inside the loop
  const KObject& o = s.g;
  const float a0x = o.a[0], a0y = o.a[1], a0z = o.a[2], a1x = o.a[3], a1y = o.a[4], a1z = o.a[5];
  const float a2x = o.a[6], a2y = o.a[7], a2z = o.a[8];
  const float ox = o.o[0], oy = o.o[1], oz = o.o[2], radius = o.h[0];
  const int id = o.id;
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    const bool m = obj[i] == id;
    const float ti = t[i];  // other lanes compute garbage, masked at the end
    const float x_ = dx[i], y_ = dy[i];
    const float px = ox + ti * (a0x * x_ + a0y * y_ + a0z);
    const float py = oy + ti * (a1x * x_ + a1y * y_ + a1z);
    const float pz = oz + ti * (a2x * x_ + a2y * y_ + a2z);
    const int pt = part[i];
    float mx, my, mz;  // outward normal
    float u, v;        // texture coordinates
    if (kType == 0)
    {
      mx = a2x;
      my = a2y;
      mz = a2z;
      u = px;
      v = py;
    }
    else if (kType == 1)
    {
      // Face axis weights (one is 1) instead of selects: the loop vectorises.
      const float w0 = static_cast<float>(pt < 2), w2 = static_cast<float>(pt >= 4);
      const float w1 = 1.f - w0 - w2;
      const float sg = 1.f - 2.f * static_cast<float>(pt & 1);
      mx = sg * (w0 * a0x + w1 * a1x + w2 * a2x);
      my = sg * (w0 * a0y + w1 * a1y + w2 * a2y);
      mz = sg * (w0 * a0z + w1 * a1z + w2 * a2z);
      u = w0 * py + (1.f - w0) * px;
      v = w2 * py + (1.f - w2) * pz;
    }
    else
    {
      const float len = std::sqrt(px * px + py * py);
      const float il = 1.f / fmax2(len, 1e-20f);
      const float sx = (a0x * px + a1x * py) * il, sy = (a0y * px + a1y * py) * il, sz = (a0z * px + a1z * py) * il;
      const float ws = static_cast<float>(pt == 0), wc = (1.f - ws) * (pt == 1 ? 1.f : -1.f);
      mx = ws * sx + wc * a2x;
      my = ws * sy + wc * a2y;
      mz = ws * sz + wc * a2z;
      u = ws * (kTex == 0 ? 0.f : radius * atan2Approx(py, px)) + (1.f - ws) * px;
      v = ws * pz + (1.f - ws) * py;
    }
    // Shade the side the camera sees (planes are two-sided).
    const float facing = mx * x_ + my * y_ + mz;
    const float fl = facing > 0.f ? -1.f : 1.f;
    float alb = s.albedo;
    int par = 0;
    float tu_out = 0.f, tv_out = 0.f;
    if (kTex == 1)
    {
      const int k = static_cast<int>(floorFast(u * s.inv_scale)) + static_cast<int>(floorFast(v * s.inv_scale));
      par = k & 1;
      alb = par ? s.albedo * (1.f - s.contrast) : s.albedo;
    }
    else if (kTex == 2)
    {
      // Noise: the lookup (a gather) is noiseLanes(); here only its texel coordinates.
      tu_out = u * s.inv_scale * 16.f + s.off_u;
      tv_out = v * s.inv_scale * 16.f + s.off_v;
    }
    else if (kTex == 3)
    {
      const float x = (px + s.half_w) * s.inv_square, y = (py + s.half_h) * s.inv_square;
      const bool inside = (x >= 0.f) & (y >= 0.f) & (x < static_cast<float>(s.cols)) & (y < static_cast<float>(s.rows));
      // Clamped before the conversion: lanes that missed the board carry any x, y (even inf).
      const int ci = static_cast<int>(fmin2(fmax2(x, 0.f), static_cast<float>(s.cols)));
      const int cj = static_cast<int>(fmin2(fmax2(y, 0.f), static_cast<float>(s.rows)));
      const bool dark = inside & (((ci + cj) & 1) == 0);
      par = dark ? 1 : 0;
      alb = dark ? s.dark_albedo : s.albedo;
    }
    const float onx = nx[i], ony = ny[i], onz = nz[i], oal = albedo[i], otu = tu[i], otv = tv[i];
    const int32_t opa = parity[i];
    tu[i] = m ? tu_out : otu;
    tv[i] = m ? tv_out : otv;
    nx[i] = m ? fl * mx : onx;
    ny[i] = m ? fl * my : ony;
    nz[i] = m ? fl * mz : onz;
    albedo[i] = m ? alb : oal;
    parity[i] = m ? par : opa;
  }
}

template <int kType>
SL_INLINE void surfaceType(const KSurface& s, const float* dx, const float* dy, const float* t, const int32_t* obj,
                           const int32_t* part, int n, float* nx, float* ny, float* nz, float* albedo, int32_t* parity,
                           float* tu, float* tv)
{
  switch (s.texture)
  {
    case 1:
      surfaceBody<kType, 1>(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
      break;
    case 2:
      surfaceBody<kType, 2>(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
      break;
    case 3:
      surfaceBody<kType, 3>(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
      break;
    default:
      surfaceBody<kType, 0>(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
      break;
  }
}

SL_SIMD void surfacePlane(const KSurface& s, const float* dx, const float* dy, const float* t, const int32_t* obj,
                          const int32_t* part, int n, float* nx, float* ny, float* nz, float* albedo, int32_t* parity,
                          float* tu, float* tv)
{
  surfaceType<0>(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
}

SL_SIMD void surfaceBox(const KSurface& s, const float* dx, const float* dy, const float* t, const int32_t* obj,
                        const int32_t* part, int n, float* nx, float* ny, float* nz, float* albedo, int32_t* parity,
                        float* tu, float* tv)
{
  surfaceType<1>(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
}

SL_SIMD void surfaceCylinder(const KSurface& s, const float* dx, const float* dy, const float* t, const int32_t* obj,
                             const int32_t* part, int n, float* nx, float* ny, float* nz, float* albedo,
                             int32_t* parity, float* tu, float* tv)
{
  surfaceType<2>(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
}

// The noise texture needs gathers: the compiler does not vectorise those for generic x86-64 tuning,
// so an AVX2 version is written out and chosen at run time; the portable loop is the reference.
SL_INLINE float noiseAt(const float* tex, float x, float y)
{
  const float fx0 = floorFast(x), fy0 = floorFast(y);
  const float fx = x - fx0, fy = y - fy0;
  const int x0 = static_cast<int>(fx0) & 255, y0 = static_cast<int>(fy0) & 255;
  const int x1 = (x0 + 1) & 255, y1 = (y0 + 1) & 255;
  return (tex[y0 * 256 + x0] * (1.f - fx) + tex[y0 * 256 + x1] * fx) * (1.f - fy) +
         (tex[y1 * 256 + x0] * (1.f - fx) + tex[y1 * 256 + x1] * fx) * fy;
}

void noiseScalar(int id, float contrast, const float* tex, const int32_t* obj, const float* tu, const float* tv, int n,
                 float* albedo)
{
  for (int i = 0; i < n; ++i)
    if (obj[i] == id)
      albedo[i] *= 1.f - contrast * noiseAt(tex, tu[i], tv[i]);
}

#ifdef SL_HAVE_AVX2_KERNELS
__attribute__((target("avx2,fma"))) void noiseAvx2(int id, float contrast, const float* tex, const int32_t* obj,
                                                   const float* tu, const float* tv, int n, float* albedo)
{
  const __m256i vid = _mm256_set1_epi32(id), mask = _mm256_set1_epi32(255), i1 = _mm256_set1_epi32(1);
  const __m256 one = _mm256_set1_ps(1.f), vc = _mm256_set1_ps(contrast);
  for (int i = 0; i + 8 <= n; i += 8)
  {
    const __m256 m =
        _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(obj + i)), vid));
    if (_mm256_movemask_ps(m) == 0)
      continue;
    const __m256 x = _mm256_loadu_ps(tu + i), y = _mm256_loadu_ps(tv + i);
    const __m256 fx0 = _mm256_floor_ps(x), fy0 = _mm256_floor_ps(y);
    const __m256 fx = _mm256_sub_ps(x, fx0), fy = _mm256_sub_ps(y, fy0);
    const __m256i x0 = _mm256_and_si256(_mm256_cvttps_epi32(fx0), mask);
    const __m256i y0 = _mm256_and_si256(_mm256_cvttps_epi32(fy0), mask);
    const __m256i x1 = _mm256_and_si256(_mm256_add_epi32(x0, i1), mask);
    const __m256i y1 = _mm256_and_si256(_mm256_add_epi32(y0, i1), mask);
    const __m256i r0 = _mm256_slli_epi32(y0, 8), r1 = _mm256_slli_epi32(y1, 8);
    const __m256 a = _mm256_i32gather_ps(tex, _mm256_add_epi32(r0, x0), 4);
    const __m256 b = _mm256_i32gather_ps(tex, _mm256_add_epi32(r0, x1), 4);
    const __m256 c = _mm256_i32gather_ps(tex, _mm256_add_epi32(r1, x0), 4);
    const __m256 d = _mm256_i32gather_ps(tex, _mm256_add_epi32(r1, x1), 4);
    const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(b, a), a);
    const __m256 bottom = _mm256_fmadd_ps(fx, _mm256_sub_ps(d, c), c);
    const __m256 noise = _mm256_fmadd_ps(fy, _mm256_sub_ps(bottom, top), top);
    const __m256 factor = _mm256_fnmadd_ps(vc, noise, one);
    const __m256 al = _mm256_loadu_ps(albedo + i);
    _mm256_storeu_ps(albedo + i, _mm256_blendv_ps(al, _mm256_mul_ps(al, factor), m));
  }
}
#endif
}  // namespace

void surfaceLanes(const KSurface& s, const float* dx, const float* dy, const float* t, const int32_t* obj,
                  const int32_t* part, int n, float* nx, float* ny, float* nz, float* albedo, int32_t* parity,
                  float* tu, float* tv)
{
  switch (s.g.type)
  {
    case 0:
      surfacePlane(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
      break;
    case 1:
      surfaceBox(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
      break;
    default:
      surfaceCylinder(s, dx, dy, t, obj, part, n, nx, ny, nz, albedo, parity, tu, tv);
      break;
  }
}

void noiseLanes(int id, float contrast, const float* noise_texture, const int32_t* obj, const float* tu,
                const float* tv, int n, float* albedo)
{
#ifdef SL_HAVE_AVX2_KERNELS
  if (haveAvx2() && n % 8 == 0)
  {
    noiseAvx2(id, contrast, noise_texture, obj, tu, tv, n, albedo);
    return;
  }
#endif
  noiseScalar(id, contrast, noise_texture, obj, tu, tv, n, albedo);
}

}  // namespace sim
}  // namespace sl_sim
