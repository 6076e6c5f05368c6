#pragma once
/// @file ray_approach.h
/// @brief Where a camera ray passes a projector ray: the decoder's per-candidate geometry, one ray
/// at a time and two at a time (SSE2 where the target has it), with identical results (ROS-free).

#include <Eigen/Core>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sl_decoder
{

/// @brief The closest approach of a camera ray and a projector ray.
struct RayApproach
{
  double denom = 0.0;        ///< 1 - cos^2 of the angle between the rays (tiny when parallel)
  double z = 0.0;            ///< camera z of the camera ray's closest point, m
  double u = 0.0;            ///< distance along the projector ray to its closest point, m
  double epipolar_px = 0.0;  ///< the gap between the rays seen from the camera, px
};

/// @brief The camera side of the approach: the unit camera ray and what every candidate shares.
struct CameraRayTerms
{
  Eigen::Vector3d d1;  ///< unit direction of the camera ray (from the camera centre)
  double d1o;          ///< d1 . o
  Eigen::Vector3d o;   ///< the projector centre, camera frame, m
  double fx;           ///< camera focal length, px
};

/**
 * @brief The closest approach of camera ray @p cam and projector ray o + u d2.
 * @param d2 unit direction of the projector ray; @param d2o d2 . o.
 * Parallel rays give a denom below 1e-12 and values to be ignored (infinite or NaN, never a trap).
 */
inline RayApproach rayApproach(const CameraRayTerms& cam, const Eigen::Vector3d& d2, double d2o)
{
  RayApproach r;
  const double c = cam.d1.dot(d2);
  r.denom = 1.0 - c * c;
  const double s = (cam.d1o - c * d2o) / r.denom;
  r.u = (c * cam.d1o - d2o) / r.denom;
  r.z = s * cam.d1.z();
  const double gap = (s * cam.d1 - (cam.o + r.u * d2)).norm();
  r.epipolar_px = gap / r.z * cam.fx;
  return r;
}

/// @brief rayApproach() for two projector rays at once: the same operations in the same order,
/// so bit for bit the same results (SSE2 lanes; two calls where the target lacks SSE2).
inline void rayApproach2(const CameraRayTerms& cam, const Eigen::Vector3d& a, double ao, const Eigen::Vector3d& b,
                         double bo, RayApproach& ra, RayApproach& rb)
{
#if defined(__SSE2__)
  const __m128d x1 = _mm_set1_pd(cam.d1.x()), y1 = _mm_set1_pd(cam.d1.y()), z1 = _mm_set1_pd(cam.d1.z());
  const __m128d x2 = _mm_set_pd(b.x(), a.x()), y2 = _mm_set_pd(b.y(), a.y()), z2 = _mm_set_pd(b.z(), a.z());
  const __m128d d1o = _mm_set1_pd(cam.d1o), d2o = _mm_set_pd(bo, ao);
  // Eigen's 3-vector dot and squared norm add (x + y) + z.
  const __m128d c = _mm_add_pd(_mm_add_pd(_mm_mul_pd(x1, x2), _mm_mul_pd(y1, y2)), _mm_mul_pd(z1, z2));
  const __m128d denom = _mm_sub_pd(_mm_set1_pd(1.0), _mm_mul_pd(c, c));
  const __m128d s = _mm_div_pd(_mm_sub_pd(d1o, _mm_mul_pd(c, d2o)), denom);
  const __m128d u = _mm_div_pd(_mm_sub_pd(_mm_mul_pd(c, d1o), d2o), denom);
  const __m128d z = _mm_mul_pd(s, z1);
  const __m128d gx = _mm_sub_pd(_mm_mul_pd(s, x1), _mm_add_pd(_mm_set1_pd(cam.o.x()), _mm_mul_pd(u, x2)));
  const __m128d gy = _mm_sub_pd(_mm_mul_pd(s, y1), _mm_add_pd(_mm_set1_pd(cam.o.y()), _mm_mul_pd(u, y2)));
  const __m128d gz = _mm_sub_pd(_mm_mul_pd(s, z1), _mm_add_pd(_mm_set1_pd(cam.o.z()), _mm_mul_pd(u, z2)));
  const __m128d gap = _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(gx, gx), _mm_mul_pd(gy, gy)), _mm_mul_pd(gz, gz)));
  const __m128d epipolar = _mm_mul_pd(_mm_div_pd(gap, z), _mm_set1_pd(cam.fx));
  _mm_storel_pd(&ra.denom, denom);
  _mm_storeh_pd(&rb.denom, denom);
  _mm_storel_pd(&ra.z, z);
  _mm_storeh_pd(&rb.z, z);
  _mm_storel_pd(&ra.u, u);
  _mm_storeh_pd(&rb.u, u);
  _mm_storel_pd(&ra.epipolar_px, epipolar);
  _mm_storeh_pd(&rb.epipolar_px, epipolar);
#else
  ra = rayApproach(cam, a, ao);
  rb = rayApproach(cam, b, bo);
#endif
}

}  // namespace sl_decoder
