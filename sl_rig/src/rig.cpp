#include "sl_rig/rig.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sl_projector
{

Eigen::Vector2d PinholeModel::distort(const Eigen::Vector2d& n) const
{
  const double k1 = dist[0], k2 = dist[1], p1 = dist[2], p2 = dist[3], k3 = dist[4];
  const double x = n.x(), y = n.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return { x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
           y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y };
}

Eigen::Vector2d PinholeModel::undistort(const Eigen::Vector2d& d) const
{
  if (!distorted())
    return d;
  // Fixed point x = (d - tangential(x)) / radial(x), refined by Newton steps on the residual.
  Eigen::Vector2d x = d;
  for (int i = 0; i < 20; ++i)
  {
    const double k1 = dist[0], k2 = dist[1], p1 = dist[2], p2 = dist[3], k3 = dist[4];
    const double r2 = x.squaredNorm();
    const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const Eigen::Vector2d tangential(2.0 * p1 * x.x() * x.y() + p2 * (r2 + 2.0 * x.x() * x.x()),
                                     p1 * (r2 + 2.0 * x.y() * x.y()) + 2.0 * p2 * x.x() * x.y());
    const Eigen::Vector2d next = (d - tangential) / radial;
    if ((next - x).squaredNorm() < 1e-24)
    {
      x = next;
      break;
    }
    x = next;
  }
  // Two Newton iterations with a numerical Jacobian remove what is left of the fixed-point error.
  for (int i = 0; i < 2; ++i)
  {
    const Eigen::Vector2d r = distort(x) - d;
    const double h = 1e-7;
    Eigen::Matrix2d J;
    J.col(0) = (distort(x + Eigen::Vector2d(h, 0.0)) - distort(x)) / h;
    J.col(1) = (distort(x + Eigen::Vector2d(0.0, h)) - distort(x)) / h;
    x -= J.inverse() * r;
  }
  return x;
}

Eigen::Vector2d PinholeModel::project(const Eigen::Vector3d& p) const
{
  if (!(p.z() > 0.0))
    return { std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN() };
  const Eigen::Vector2d d = distort(Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()));
  return { fx * d.x() + cx, fy * d.y() + cy };
}

Eigen::Vector3d PinholeModel::ray(const Eigen::Vector2d& pixel) const
{
  const Eigen::Vector2d n = undistort(Eigen::Vector2d((pixel.x() - cx) / fx, (pixel.y() - cy) / fy));
  return { n.x(), n.y(), 1.0 };
}

bool PinholeModel::distorted() const
{
  for (double d : dist)
    if (d != 0.0)
      return true;
  return false;
}

double LensOptics::defocusPerInverseDepth(double f_px) const
{
  const double f = f_px * pixel_pitch;
  return (f / f_number) * f_px * focus_distance / std::max(focus_distance - f, 1e-6);
}

double LensOptics::defocusDiameter(double f_px, double depth) const
{
  return defocusPerInverseDepth(f_px) * std::abs(1.0 / depth - 1.0 / focus_distance);
}

RigidTransform RigidTransform::inverse() const
{
  RigidTransform inv;
  inv.rotation = rotation.transpose();
  inv.translation = -(inv.rotation * translation);
  return inv;
}

Eigen::Matrix3d rotationFromRpy(const Eigen::Vector3d& rpy)
{
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

RigidTransform Mount::cameraOpticalInParent() const
{
  RigidTransform link;
  link.rotation = rotationFromRpy(rpy);
  link.translation = xyz;
  // Optical axes in camera_link: x_opt = -y_link, y_opt = -z_link, z_opt = x_link.
  Eigen::Matrix3d optical_in_link;
  optical_in_link << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  RigidTransform optical;
  optical.rotation = link.rotation * optical_in_link;
  optical.translation = link.translation;
  return optical;
}

void Rig::projectorRay(const Eigen::Vector2d& projector_pixel, Eigen::Vector3d& origin,
                       Eigen::Vector3d& direction) const
{
  origin = projector_pose.translation;
  direction = (projector_pose.rotation * projector.ray(projector_pixel)).normalized();
}

bool Rig::triangulate(const Eigen::Vector2d& camera_pixel, const Eigen::Vector2d& projector_pixel,
                      Eigen::Vector3d& point, double* ray_distance) const
{
  const Eigen::Vector3d d1 = camera.ray(camera_pixel).normalized();
  Eigen::Vector3d o2, d2;
  projectorRay(projector_pixel, o2, d2);
  // Minimise |s d1 - (o2 + u d2)|: the normal equations of the two ray parameters.
  const double b = d1.dot(d2);
  const double denom = 1.0 - b * b;
  if (denom < 1e-12)
    return false;
  const double d1o = d1.dot(o2), d2o = d2.dot(o2);
  const double s = (d1o - b * d2o) / denom;
  const double u = (b * d1o - d2o) / denom;
  if (!(s > 0.0))
    return false;
  point = s * d1;
  if (ray_distance)
    *ray_distance = (point - (o2 + u * d2)).norm();
  return true;
}

}  // namespace sl_projector
