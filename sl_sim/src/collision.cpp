// Ground-truth collision: exact horizontal distances from the robot's axis to the scene's objects
// within the robot's heights (the projection of each object's part between two heights onto the
// floor, and that shape's distance from the axis).
#include "sl_sim/collision.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "geometry.h"

namespace sl_sim
{

namespace
{
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Prepared = sim::PreparedObject<double>;
constexpr double kInf = std::numeric_limits<double>::infinity();

double cross(const Vec2& o, const Vec2& a, const Vec2& b)
{
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Distance from the origin to the segment a-b.
double segmentDistance(const Vec2& a, const Vec2& b)
{
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d).norm();
}

// Distance from the origin to the convex hull of p[0..n) (0 inside; +inf for no points). Reorders p.
template <size_t N>
double hullDistance(std::array<Vec2, N>& p, size_t n)
{
  if (n == 0)
    return kInf;
  std::sort(p.begin(), p.begin() + n,
            [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  // Andrew's monotone chain, counter-clockwise, collinear points dropped.
  std::array<Vec2, N + 1> h;
  size_t k = 0;
  for (size_t i = 0; i < n; ++i)
  {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0.0)
      --k;
    h[k++] = p[i];
  }
  for (size_t i = n - 1, lower = k + 1; i-- > 0;)
  {
    while (k >= lower && cross(h[k - 2], h[k - 1], p[i]) <= 0.0)
      --k;
    h[k++] = p[i];
  }
  if (k > 1)
    --k;  // the first point closed the chain
  if (k == 1)
    return h[0].norm();
  if (k == 2)
    return segmentDistance(h[0], h[1]);
  bool inside = true;
  double best = kInf;
  for (size_t i = 0; i < k; ++i)
  {
    const Vec2& a = h[i];
    const Vec2& b = h[(i + 1) % k];
    inside = inside && cross(a, b, Vec2::Zero()) >= 0.0;
    best = std::min(best, segmentDistance(a, b));
  }
  return inside ? 0.0 : best;
}

// A box (dims 3) or a rectangle (dims 2): its vertices between the heights and its edges' crossings
// of them span the clipped solid, whose shadow on the floor is their convex hull.
double polytopeDistance(const Prepared& o, int dims, double z0, double z1)
{
  const int nv = 1 << dims;
  std::array<Vec3, 8> v;
  for (int i = 0; i < nv; ++i)
  {
    v[i] = o.centre;
    for (int k = 0; k < dims; ++k)
      v[i] += (((i >> k) & 1) ? 1.0 : -1.0) * o.half[k] * o.axes.col(k);
  }
  std::array<Vec2, 32> p;  // at most 8 vertices + 12 edges x 2 heights
  size_t n = 0;
  for (int i = 0; i < nv; ++i)
    if (v[i].z() >= z0 && v[i].z() <= z1)
      p[n++] = v[i].head<2>();
  for (int i = 0; i < nv; ++i)
    for (int k = 0; k < dims; ++k)
    {
      if ((i >> k) & 1)
        continue;
      const Vec3& a = v[i];
      const Vec3& b = v[i | (1 << k)];
      for (const double level : { z0, z1 })
        if ((a.z() - level) * (b.z() - level) < 0.0)
          p[n++] = (a + (level - a.z()) / (b.z() - a.z()) * (b - a)).head<2>();
    }
  return hullDistance(p, n);
}

// An infinite plane n . x = d: its points between the heights project to the strip
// n_xy . q in [d - n_z z1, d - n_z z0] (all or nothing for a horizontal plane).
double infinitePlaneDistance(const Prepared& o, double z0, double z1)
{
  const Vec3 n = o.axes.col(2);
  const double d = n.dot(o.centre);
  const double a = d - n.z() * z0, b = d - n.z() * z1;
  const double lo = std::min(a, b), hi = std::max(a, b);
  if (lo <= 0.0 && hi >= 0.0)
    return 0.0;
  const double nh = n.head<2>().norm();
  return nh > 0.0 ? std::min(std::abs(lo), std::abs(hi)) / nh : kInf;
}

// Minimum of a convex function on [lo, hi] (golden-section search down to 1e-12 of the argument).
template <typename F>
double minimizeConvex(const F& f, double lo, double hi)
{
  constexpr double kInvPhi = 0.6180339887498949;
  double x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 100 && hi - lo > 1e-12; ++i)
  {
    if (f1 <= f2)
    {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kInvPhi * (hi - lo);
      f1 = f(x1);
    }
    else
    {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kInvPhi * (hi - lo);
      f2 = f(x2);
    }
  }
  return std::min({ f1, f2, f(lo), f(hi) });
}

// A solid cylinder. Upright: its shadow is its disc. Otherwise the distance of the slice at height
// z is convex in z, and within a slice the distance of the chord cut from the cross-section disc at
// axis position s is convex in s (the distance from a line to a convex set is convex along it):
// two nested one-dimensional searches, each chord's distance in closed form.
double cylinderDistance(const Prepared& o, double z0, double z1)
{
  const Vec3 a = o.axes.col(2);
  const Vec3& c = o.centre;
  const double r = o.half.x(), h = o.half.z();
  const double axy = a.head<2>().norm();
  const double extent = std::abs(a.z()) * h + r * axy;  // half the cylinder's height range
  const double zlo = std::max(z0, c.z() - extent), zhi = std::min(z1, c.z() + extent);
  if (zlo > zhi)
    return kInf;
  if (axy < 1e-12)
    return std::max(0.0, c.head<2>().norm() - r);
  const Vec3 u1 = Vec3(a.y(), -a.x(), 0.0) / axy;  // horizontal, across the axis
  const Vec3 u2 = a.cross(u1);                     // in the cross-section, u2.z() = -axy
  const Vec2 along = u1.head<2>();
  // The chord of the cross-section disc at axis position s at height z: centre, half length along u1.
  const auto chord = [&](double z, double s)
  {
    const Vec3 m = c + s * a;
    const double beta = (z - m.z()) / u2.z();
    const double half = std::sqrt(std::max(0.0, r * r - beta * beta));
    const Vec2 q = (m + beta * u2).head<2>();
    return (q + std::clamp(-q.dot(along), -half, half) * along).norm();
  };
  const auto slice = [&](double z)
  {
    // Axis positions whose cross-section reaches height z: |z - c.z - s a.z| <= r axy.
    double lo = -h, hi = h;
    if (a.z() != 0.0)
    {
      const double s1 = (z - c.z() - r * axy) / a.z(), s2 = (z - c.z() + r * axy) / a.z();
      lo = std::max(lo, std::min(s1, s2));
      hi = std::min(hi, std::max(s1, s2));
    }
    if (lo > hi)  // rounding at the ends of the height range
      lo = hi = 0.5 * (lo + hi);
    return minimizeConvex([&](double s) { return chord(z, s); }, lo, hi);
  };
  return minimizeConvex(slice, zlo, zhi);
}

double preparedDistance(const Prepared& o, double z0, double z1)
{
  if (!(z0 <= z1))
    return kInf;
  switch (o.type)
  {
    case ObjectType::Plane:
      return o.infinite ? infinitePlaneDistance(o, z0, z1) : polytopeDistance(o, 2, z0, z1);
    case ObjectType::Box:
      return polytopeDistance(o, 3, z0, z1);
    case ObjectType::Cylinder:
    default:
      return cylinderDistance(o, z0, z1);
  }
}

void assignName(const Scene& scene, int index, std::string& out)
{
  const std::string& name = scene.objects[static_cast<size_t>(index)].name;
  if (!name.empty())
    out.assign(name);
  else
    out = objectName(scene, index);
}
}  // namespace

std::string objectName(const Scene& scene, int index)
{
  if (index < 0 || static_cast<size_t>(index) >= scene.objects.size())
    return "object #" + std::to_string(index);
  const SceneObject& o = scene.objects[static_cast<size_t>(index)];
  return o.name.empty() ? std::string(objectTypeName(o.type)) + " #" + std::to_string(index) : o.name;
}

double horizontalDistance(const SceneObject& object, const Eigen::Isometry3d& object_in_frame, double z_min,
                          double z_max)
{
  Prepared o;
  o.set(object, object_in_frame, 0);
  return preparedDistance(o, z_min, z_max);
}

void computeCollision(const Scene& scene, const Eigen::Isometry3d& robot_in_world, const ContactSettings& s,
                      CollisionReport& report)
{
  s.validate();
  report.colliding = false;
  report.objects.clear();
  report.min_clearance = kInf;
  report.nearest_object = -1;
  const Eigen::Isometry3d world_in_robot = robot_in_world.inverse();
  const double z0 = s.contact_min_height, z1 = s.robot_height;
  for (size_t i = 0; i < scene.objects.size(); ++i)
  {
    const SceneObject& obj = scene.objects[i];
    if (obj.floor)
      continue;
    Prepared o;
    o.set(obj, world_in_robot * obj.pose, static_cast<int>(i));
    // Cheap bounds first: the object's heights, and its bounding sphere's horizontal distance.
    if (o.support(Vec3::UnitZ()) < z0 || -o.support(-Vec3::UnitZ()) > z1)
      continue;
    const double lower = o.centre.head<2>().norm() - o.boundingRadius() - s.robot_radius;
    if (lower > 0.0 && lower >= report.min_clearance)
      continue;
    const double clearance = preparedDistance(o, z0, z1) - s.robot_radius;
    if (!std::isfinite(clearance))
      continue;
    if (clearance <= 0.0)
    {
      report.colliding = true;
      report.objects.push_back(static_cast<int>(i));
    }
    if (clearance < report.min_clearance)
    {
      report.min_clearance = clearance;
      report.nearest_object = static_cast<int>(i);
    }
  }
  report.names.resize(report.objects.size());
  for (size_t k = 0; k < report.objects.size(); ++k)
    assignName(scene, report.objects[k], report.names[k]);
  if (report.nearest_object >= 0)
    assignName(scene, report.nearest_object, report.nearest_name);
  else
    report.nearest_name.clear();
}

CollisionReport computeCollision(const Scene& scene, const Eigen::Isometry3d& robot_in_world,
                                 const ContactSettings& settings)
{
  CollisionReport report;
  computeCollision(scene, robot_in_world, settings, report);
  return report;
}

}  // namespace sl_sim
