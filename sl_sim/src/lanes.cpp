// The renderer's data-parallel kernels (see lanes.h). Loops are branch-free (selects instead of
// branches) so that they vectorise; built with -fno-math-errno so that sqrt vectorises too.
#include "lanes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(SL_SIM_NO_CLONES)
#define SL_SIMD __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define SL_SIMD
#endif
#define SL_INLINE inline __attribute__((always_inline))

namespace sl_sim
{
namespace sim
{

namespace
{
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

SL_INLINE float fmin2(float a, float b)
{
  return a < b ? a : b;
}
SL_INLINE float fmax2(float a, float b)
{
  return a > b ? a : b;
}

// floor without a library call (vectorises without SSE4.1 rounding): |x| < 2^31.
SL_INLINE float floorFast(float x)
{
  const float t = static_cast<float>(static_cast<int32_t>(x));
  return t - static_cast<float>(x < t);
}

// log2 to about 0.005 (exponent plus a quadratic in the mantissa); x > 0.
SL_INLINE float log2Approx(float x)
{
  const int32_t bits = __builtin_bit_cast(int32_t, x);
  const float e = static_cast<float>((bits >> 23) - 127);
  const float m = __builtin_bit_cast(float, (bits & 0x007fffff) | 0x3f800000);
  const float f = m - 1.f;
  return e + f * (1.3465f - 0.3465f * f);
}

// 2^x to about 0.2 % for x in [-126, 0]; 0 below.
SL_INLINE float exp2Approx(float x)
{
  const float xc = fmax2(x, -126.f);
  const float fl = floorFast(xc);
  const float f = xc - fl;
  const float p = 1.f + f * (0.6565f + f * (0.2228f + f * 0.0792f));  // 2^f on [0, 1)
  const float scale = __builtin_bit_cast(float, (static_cast<int32_t>(fl) + 127) << 23);
  return x < -126.f ? 0.f : p * scale;
}

// atan2 to about 1e-3 rad (for texture coordinates only).
SL_INLINE float atan2Approx(float y, float x)
{
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float mx = fmax2(ax, ay), mn = fmin2(ax, ay);
  const float a = mn / fmax2(mx, 1e-30f);
  const float s = a * a;
  float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  r = ay > ax ? 1.57079637f - r : r;
  r = x < 0.f ? 3.14159274f - r : r;
  return y < 0.f ? -r : r;
}

// ---------------------------------------------------------------------------------------------
// Intersections.

SL_INLINE bool planeBody(const KObject& o, const float* __restrict dx, const float* __restrict dy,
                         const float* __restrict dz, int n, float tmin, float* __restrict t, int32_t* __restrict obj,
                         int32_t* __restrict part, const int32_t* __restrict self)
{
  const float a0x = o.a[0], a0y = o.a[1], a0z = o.a[2], a1x = o.a[3], a1y = o.a[4], a1z = o.a[5];
  const float a2x = o.a[6], a2y = o.a[7], a2z = o.a[8];
  const float ox = o.o[0], oy = o.o[1], oz = o.o[2], hx = o.h[0], hy = o.h[1];
  const int id = o.id;
  int any = 0;
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    const float x_ = dx[i], y_ = dy[i], z_ = dz[i];
    const float lz = a2x * x_ + a2y * y_ + a2z * z_;
    const float th = -oz / lz;
    const float x = ox + th * (a0x * x_ + a0y * y_ + a0z * z_);
    const float y = oy + th * (a1x * x_ + a1y * y_ + a1z * z_);
    bool ok = (th > tmin) & (th < t[i]) & (std::fabs(x) <= hx) & (std::fabs(y) <= hy);
    ok = ok & (self[i] != id);
    t[i] = ok ? th : t[i];
    obj[i] = ok ? id : obj[i];
    part[i] = ok ? 0 : part[i];
    any |= ok;
  }
  return any != 0;
}

SL_INLINE bool boxBody(const KObject& o, const float* __restrict dx, const float* __restrict dy,
                       const float* __restrict dz, int n, float tmin, float* __restrict t, int32_t* __restrict obj,
                       int32_t* __restrict part, const int32_t* __restrict self)
{
  const float a0x = o.a[0], a0y = o.a[1], a0z = o.a[2], a1x = o.a[3], a1y = o.a[4], a1z = o.a[5];
  const float a2x = o.a[6], a2y = o.a[7], a2z = o.a[8];
  const float ox = o.o[0], oy = o.o[1], oz = o.o[2], hx = o.h[0], hy = o.h[1], hz = o.h[2];
  const int id = o.id;
  int any = 0;
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    const float x_ = dx[i], y_ = dy[i], z_ = dz[i];
    const float lx = a0x * x_ + a0y * y_ + a0z * z_;
    const float ly = a1x * x_ + a1y * y_ + a1z * z_;
    const float lz = a2x * x_ + a2y * y_ + a2z * z_;
    const float ix = 1.f / lx, iy = 1.f / ly, iz = 1.f / lz;
    const float tx0 = (-hx - ox) * ix, tx1 = (hx - ox) * ix;
    const float ty0 = (-hy - oy) * iy, ty1 = (hy - oy) * iy;
    const float tz0 = (-hz - oz) * iz, tz1 = (hz - oz) * iz;
    const float txn = fmin2(tx0, tx1), txf = fmax2(tx0, tx1);
    const float tyn = fmin2(ty0, ty1), tyf = fmax2(ty0, ty1);
    const float tzn = fmin2(tz0, tz1), tzf = fmax2(tz0, tz1);
    const float tn = fmax2(txn, fmax2(tyn, tzn));
    const float tf = fmin2(txf, fmin2(tyf, tzf));
    // The faces: the slabs that gave t_near and t_far (written so that the loop vectorises).
    const int an = tn == txn ? 0 : (tn == tyn ? 2 : 4);
    const int af = tf == txf ? 0 : (tf == tyf ? 2 : 4);
    const float dn = tn == txn ? lx : (tn == tyn ? ly : lz);
    const float df = tf == txf ? lx : (tf == tyf ? ly : lz);
    const int pn = an + (dn > 0.f);   // moving along +axis, a ray enters through the -axis face
    const int pf = af + (df <= 0.f);  // ... and leaves through the +axis face
    const bool use_near = tn > tmin;
    const float th = use_near ? tn : tf;
    const int ph = use_near ? pn : pf;
    bool ok = (tn <= tf) & (th > tmin) & (th < t[i]);
    ok = ok & (self[i] != id);
    t[i] = ok ? th : t[i];
    obj[i] = ok ? id : obj[i];
    part[i] = ok ? ph : part[i];
    any |= ok;
  }
  return any != 0;
}

SL_INLINE bool cylinderBody(const KObject& o, const float* __restrict dx, const float* __restrict dy,
                            const float* __restrict dz, int n, float tmin, float* __restrict t, int32_t* __restrict obj,
                            int32_t* __restrict part, const int32_t* __restrict self)
{
  const float a0x = o.a[0], a0y = o.a[1], a0z = o.a[2], a1x = o.a[3], a1y = o.a[4], a1z = o.a[5];
  const float a2x = o.a[6], a2y = o.a[7], a2z = o.a[8];
  const float ox = o.o[0], oy = o.o[1], oz = o.o[2], r = o.h[0], hz = o.h[2];
  const float r2 = r * r;
  const float c = ox * ox + oy * oy - r2;
  const int id = o.id;
  int any = 0;
#pragma GCC ivdep
  for (int i = 0; i < n; ++i)
  {
    const float x_ = dx[i], y_ = dy[i], z_ = dz[i];
    const float lx = a0x * x_ + a0y * y_ + a0z * z_;
    const float ly = a1x * x_ + a1y * y_ + a1z * z_;
    const float lz = a2x * x_ + a2y * y_ + a2z * z_;
    const float a = lx * lx + ly * ly;
    const float b = ox * lx + oy * ly;
    const float disc = b * b - a * c;
    const float sq = std::sqrt(fmax2(disc, 0.f));
    const float inv_a = 1.f / a;
    const float ta = (-b - sq) * inv_a, tb = (-b + sq) * inv_a;
    const bool side = (disc >= 0.f) & (a > 0.f);
    const bool va = side & (ta > tmin) & (std::fabs(oz + ta * lz) <= hz);
    const bool vb = side & (tb > tmin) & (std::fabs(oz + tb * lz) <= hz);
    float best = va ? ta : (vb ? tb : kInf);
    int bp = 0;
    const float iz = 1.f / lz;
    const float tt = (hz - oz) * iz, tbt = (-hz - oz) * iz;
    const float xt = ox + tt * lx, yt = oy + tt * ly;
    const float xb = ox + tbt * lx, yb = oy + tbt * ly;
    const bool vt = (tt > tmin) & (tt < best) & (xt * xt + yt * yt <= r2);
    best = vt ? tt : best;
    bp = vt ? 1 : bp;
    const bool vbt = (tbt > tmin) & (tbt < best) & (xb * xb + yb * yb <= r2);
    best = vbt ? tbt : best;
    bp = vbt ? 2 : bp;
    bool ok = best < t[i];
    ok = ok & (self[i] != id);
    t[i] = ok ? best : t[i];
    obj[i] = ok ? id : obj[i];
    part[i] = ok ? bp : part[i];
    any |= ok;
  }
  return any != 0;
}

SL_SIMD bool intersectPlane(const KObject& o, const float* dx, const float* dy, const float* dz, int n, float tmin,
                            float* t, int32_t* obj, int32_t* part, const int32_t* self)
{
  return planeBody(o, dx, dy, dz, n, tmin, t, obj, part, self);
}

SL_SIMD bool intersectBox(const KObject& o, const float* dx, const float* dy, const float* dz, int n, float tmin,
                          float* t, int32_t* obj, int32_t* part, const int32_t* self)
{
  return boxBody(o, dx, dy, dz, n, tmin, t, obj, part, self);
}

SL_SIMD bool intersectCylinder(const KObject& o, const float* dx, const float* dy, const float* dz, int n, float tmin,
                               float* t, int32_t* obj, int32_t* part, const int32_t* self)
{
  return cylinderBody(o, dx, dy, dz, n, tmin, t, obj, part, self);
}

// ---------------------------------------------------------------------------------------------
// Surfaces: Type 0 plane, 1 box, 2 cylinder; Tex 0 none, 1 checker, 2 noise, 3 checkerboard.

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
      const int ci = static_cast<int>(fmax2(x, 0.f)), cj = static_cast<int>(fmax2(y, 0.f));
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
}  // namespace

SL_SIMD float maxLanes(const float* __restrict x, int n)
{
  int32_t m = 0;  // non-negative floats order like their bit patterns
  for (int i = 0; i < n; ++i)
  {
    const int32_t b = __builtin_bit_cast(int32_t, x[i]);
    m = b > m ? b : m;
  }
  return __builtin_bit_cast(float, m);
}

bool intersectLanes(const KObject& o, const float* dx, const float* dy, const float* dz, int n, float tmin, float* t,
                    int32_t* obj, int32_t* part, const int32_t* self)
{
  switch (o.type)
  {
    case 0:
      return intersectPlane(o, dx, dy, dz, n, tmin, t, obj, part, self);
    case 1:
      return intersectBox(o, dx, dy, dz, n, tmin, t, obj, part, self);
    default:
      return intersectCylinder(o, dx, dy, dz, n, tmin, t, obj, part, self);
  }
}

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

#if defined(__x86_64__) && defined(__GNUC__) && !defined(SL_SIM_NO_CLONES)
#define SL_HAVE_AVX2_KERNELS 1
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

bool haveAvx2()
{
  static const bool have = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return have;
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

SL_SIMD void upsampleRows2(const float* __restrict src, int sw, int sh, float* __restrict dst, int dst_stride,
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
      const float a = pad[k + 1];
      out[2 * k] = 0.75f * a + 0.25f * pad[k];
      out[2 * k + 1] = 0.75f * a + 0.25f * pad[k + 2];
    }
  }
}

SL_SIMD void upsampleRows4(const float* __restrict src, int sw, int sh, float* __restrict dst, int dst_stride,
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
      out[4 * k] = 0.625f * a + 0.375f * m;
      out[4 * k + 1] = 0.875f * a + 0.125f * m;
      out[4 * k + 2] = 0.875f * a + 0.125f * p;
      out[4 * k + 3] = 0.625f * a + 0.375f * p;
    }
  }
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
