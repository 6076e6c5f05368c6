// The renderer's kernels, stage 1: nearest hits of the lanes' rays with planes, boxes and cylinders
// (see lanes.h). Loops are branch-free (selects instead of branches) so that they vectorise.
#include "lanes.h"
#include "lanes_common.h"

namespace sl_sim
{
namespace sim
{

namespace
{
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

}  // namespace sim
}  // namespace sl_sim
