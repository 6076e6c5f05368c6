#pragma once
// Internal: scene objects prepared for fast ray intersection in some frame (the world for the public
// API, the camera optical frame for the renderer), templated on the scalar type so that the public
// double-precision API and the float renderer run the same code.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "sl_sim/scene.h"

namespace sl_sim
{
namespace sim
{

/// An object in a frame: its axes and centre, and half sizes.
template <typename S>
struct PreparedObject
{
  using Vec3 = Eigen::Matrix<S, 3, 1>;
  using Mat3 = Eigen::Matrix<S, 3, 3>;

  ObjectType type = ObjectType::Plane;
  bool infinite = false;         ///< infinite plane
  int index = -1;                ///< index in the scene
  Mat3 axes = Mat3::Identity();  ///< columns: local x, y, z in the frame
  Vec3 centre = Vec3::Zero();    ///< object centre in the frame
  Vec3 half = Vec3::Zero();      ///< box: half edges; plane: half x, half y, 0; cylinder: r, r, half height

  /// Sets the object from its pose in the frame.
  void set(const SceneObject& object, const Eigen::Isometry3d& object_in_frame, int object_index)
  {
    type = object.type;
    index = object_index;
    axes = object_in_frame.linear().cast<S>();
    centre = object_in_frame.translation().cast<S>();
    infinite = object.infinite();
    switch (type)
    {
      case ObjectType::Plane:
        half = infinite ? Vec3(std::numeric_limits<S>::infinity(), std::numeric_limits<S>::infinity(), S(0))
                        : Vec3(S(object.size.x() / 2), S(object.size.y() / 2), S(0));
        break;
      case ObjectType::Box:
        half = (object.size / 2).cast<S>();
        break;
      case ObjectType::Cylinder:
        half = Vec3(S(object.size.x()), S(object.size.x()), S(object.size.z() / 2));
        break;
    }
  }

  /// A point of the frame in local coordinates.
  Vec3 toLocal(const Vec3& p) const { return axes.transpose() * (p - centre); }

  /// The largest n . x over the object (its support function); +inf for an infinite plane.
  S support(const Vec3& n) const
  {
    if (infinite)
      return std::numeric_limits<S>::infinity();
    const S c = n.dot(centre);
    const S a0 = n.dot(axes.col(0)), a1 = n.dot(axes.col(1)), a2 = n.dot(axes.col(2));
    switch (type)
    {
      case ObjectType::Plane:
      case ObjectType::Box:
        return c + std::abs(a0) * half.x() + std::abs(a1) * half.y() + std::abs(a2) * half.z();
      case ObjectType::Cylinder:
      default:
        return c + std::abs(a2) * half.z() + half.x() * std::sqrt(std::max(S(0), n.squaredNorm() - a2 * a2));
    }
  }

  /// Bounding sphere radius about the centre (infinite for infinite planes).
  S boundingRadius() const
  {
    if (infinite)
      return std::numeric_limits<S>::infinity();
    if (type == ObjectType::Cylinder)
      return std::sqrt(half.x() * half.x() + half.z() * half.z());
    return half.norm();
  }

  /**
   * Smallest t in (t_min, t_max) where origin + t d meets the object. @p origin_local is the ray
   * origin in local coordinates (toLocal(origin)), @p d the direction in the frame.
   * On a hit sets t and part (box face 0..5 = +x -x +y -y +z -z; cylinder 0 side, 1 top, 2 bottom).
   */
  bool intersect(const Vec3& origin_local, const Vec3& d, S t_min, S t_max, S& t, int& part) const
  {
    if (type == ObjectType::Plane)
      return intersectPlane(origin_local, d, t_min, t_max, t, part);
    const Vec3 dl = axes.transpose() * d;
    if (type == ObjectType::Box)
      return intersectBox(origin_local, dl, t_min, t_max, t, part);
    return intersectCylinder(origin_local, dl, t_min, t_max, t, part);
  }

  // intersect() by type; @p d in the frame, @p dl the direction in local coordinates.
  bool intersectPlane(const Vec3& o, const Vec3& d, S t_min, S t_max, S& t, int& part) const
  {
    const S dz = axes.col(2).dot(d);
    if (dz == S(0))
      return false;
    const S th = -o.z() / dz;
    if (!(th > t_min && th < t_max))
      return false;
    if (!infinite)
    {
      const S x = o.x() + th * axes.col(0).dot(d);
      const S y = o.y() + th * axes.col(1).dot(d);
      if (std::abs(x) > half.x() || std::abs(y) > half.y())
        return false;
    }
    t = th;
    part = 0;
    return true;
  }

  bool intersectBox(const Vec3& o, const Vec3& dl, S t_min, S t_max, S& t, int& part) const
  {
    S t_near = -std::numeric_limits<S>::infinity(), t_far = std::numeric_limits<S>::infinity();
    int near_axis = 0, far_axis = 0;
    bool near_neg = false, far_neg = false;
    for (int i = 0; i < 3; ++i)
    {
      if (dl[i] == S(0))
      {
        if (std::abs(o[i]) > half[i])
          return false;
        continue;
      }
      const S inv = S(1) / dl[i];
      S t0 = (-half[i] - o[i]) * inv;  // entry through the -i face when dl > 0
      S t1 = (half[i] - o[i]) * inv;
      bool neg0 = true;
      if (t0 > t1)
      {
        std::swap(t0, t1);
        neg0 = false;
      }
      if (t0 > t_near)
      {
        t_near = t0;
        near_axis = i;
        near_neg = neg0;
      }
      if (t1 < t_far)
      {
        t_far = t1;
        far_axis = i;
        far_neg = !neg0;
      }
    }
    if (t_near > t_far)
      return false;
    if (t_near > t_min && t_near < t_max)
    {
      t = t_near;
      part = 2 * near_axis + (near_neg ? 1 : 0);
      return true;
    }
    if (t_far > t_min && t_far < t_max)
    {
      t = t_far;
      part = 2 * far_axis + (far_neg ? 1 : 0);
      return true;
    }
    return false;
  }

  bool intersectCylinder(const Vec3& o, const Vec3& dl, S t_min, S t_max, S& t, int& part) const
  {
    // Cylinder: side x^2 + y^2 = r^2 with |z| <= h, caps z = +-h with x^2 + y^2 <= r^2.
    const S r = half.x(), h = half.z();
    S best = t_max;
    int best_part = -1;
    const S a = dl.x() * dl.x() + dl.y() * dl.y();
    if (a > S(0))
    {
      const S b = o.x() * dl.x() + o.y() * dl.y();
      const S c = o.x() * o.x() + o.y() * o.y() - r * r;
      const S disc = b * b - a * c;
      if (disc >= S(0))
      {
        const S sq = std::sqrt(disc);
        const S ta = (-b - sq) / a, tb = (-b + sq) / a;
        if (ta > t_min && ta < best && std::abs(o.z() + ta * dl.z()) <= h)
        {
          best = ta;
          best_part = 0;
        }
        else if (tb > t_min && tb < best && std::abs(o.z() + tb * dl.z()) <= h)
        {
          best = tb;
          best_part = 0;
        }
      }
    }
    if (dl.z() != S(0))
    {
      const S inv = S(1) / dl.z();
      for (int cap = 0; cap < 2; ++cap)
      {
        const S zc = cap == 0 ? h : -h;
        const S tc = (zc - o.z()) * inv;
        if (tc > t_min && tc < best)
        {
          const S x = o.x() + tc * dl.x(), y = o.y() + tc * dl.y();
          if (x * x + y * y <= r * r)
          {
            best = tc;
            best_part = 1 + cap;
          }
        }
      }
    }
    if (best_part < 0)
      return false;
    t = best;
    part = best_part;
    return true;
  }

  /// Unit outward normal (frame) at local point @p pl on @p part (planes: the +z side).
  Vec3 normal(const Vec3& pl, int part) const
  {
    switch (type)
    {
      case ObjectType::Plane:
        return axes.col(2);
      case ObjectType::Box:
        return (part & 1) ? Vec3(-axes.col(part >> 1)) : Vec3(axes.col(part >> 1));
      case ObjectType::Cylinder:
      default:
        if (part == 0)
        {
          const S len = std::sqrt(pl.x() * pl.x() + pl.y() * pl.y());
          return len > S(0) ? Vec3((axes.col(0) * pl.x() + axes.col(1) * pl.y()) / len) : Vec3(axes.col(0));
        }
        return part == 1 ? Vec3(axes.col(2)) : Vec3(-axes.col(2));
    }
  }

  /// Texture coordinates (m) at local point @p pl on @p part.
  Eigen::Matrix<S, 2, 1> uv(const Vec3& pl, int part) const
  {
    using Vec2 = Eigen::Matrix<S, 2, 1>;
    switch (type)
    {
      case ObjectType::Plane:
        return Vec2(pl.x(), pl.y());
      case ObjectType::Box:
      {
        const int axis = part >> 1;
        return axis == 0 ? Vec2(pl.y(), pl.z()) : (axis == 1 ? Vec2(pl.x(), pl.z()) : Vec2(pl.x(), pl.y()));
      }
      case ObjectType::Cylinder:
      default:
        if (part == 0)
          return Vec2(half.x() * std::atan2(pl.y(), pl.x()), pl.z());
        return Vec2(pl.x(), pl.y());
    }
  }
};

}  // namespace sim
}  // namespace sl_sim
