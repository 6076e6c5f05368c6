#include "cloud_conversion.h"

#include <cmath>
#include <cstring>
#include <limits>

#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2/utils.h>

namespace sl_obstacle
{
namespace
{
struct FieldReader
{
  // An offset up to 4294967295 (not int: one over 2^31 turned negative).
  std::size_t offset = 0;
  std::uint8_t datatype = 0;
  bool found = false;

  bool valid() const { return found; }

  double read(const std::uint8_t* point) const
  {
    if (datatype == sensor_msgs::PointField::FLOAT32)
    {
      float v;
      std::memcpy(&v, point + offset, sizeof(v));
      return v;
    }
    double v;
    std::memcpy(&v, point + offset, sizeof(v));
    return v;
  }
};

std::string findField(const sensor_msgs::PointCloud2& cloud, const char* name, bool required, FieldReader& reader)
{
  for (const sensor_msgs::PointField& f : cloud.fields)
  {
    if (f.name != name)
    {
      continue;
    }
    if (f.datatype != sensor_msgs::PointField::FLOAT32 && f.datatype != sensor_msgs::PointField::FLOAT64)
    {
      return required ? std::string("field ") + name + " is not FLOAT32 or FLOAT64" : std::string();
    }
    const std::size_t size = f.datatype == sensor_msgs::PointField::FLOAT32 ? 4U : 8U;
    if (f.offset + size > cloud.point_step)
    {
      return std::string("field ") + name + " lies outside point_step";
    }
    reader.offset = f.offset;
    reader.datatype = f.datatype;
    reader.found = true;
    return std::string();
  }
  return required ? std::string("no field ") + name : std::string();
}

/// Empty when the data buffer holds width x height points of point_step bytes.
std::string checkLayout(const sensor_msgs::PointCloud2& cloud)
{
  const std::size_t width = cloud.width;
  const std::size_t height = cloud.height;
  if (cloud.is_bigendian)
  {
    return "big-endian clouds are not supported";
  }
  if (width * height > 0 && (cloud.point_step == 0 || cloud.row_step < width * cloud.point_step ||
                             cloud.data.size() < (height - 1) * cloud.row_step + width * cloud.point_step))
  {
    return "data size does not match width, height, point_step and row_step";
  }
  return std::string();
}

std::string readTransform(const geometry_msgs::Transform& transform, tf2::Matrix3x3& r, tf2::Vector3& t)
{
  const tf2::Quaternion q(transform.rotation.x, transform.rotation.y, transform.rotation.z, transform.rotation.w);
  if (!(q.length2() > 0.5))
  {
    return "transform has an invalid rotation";
  }
  r = tf2::Matrix3x3(q.normalized());
  t = tf2::Vector3(transform.translation.x, transform.translation.y, transform.translation.z);
  return std::string();
}

/// The uint8 field @p name: its offset, or a message.
std::string findStateField(const sensor_msgs::PointCloud2& cloud, const char* name, std::size_t& offset)
{
  for (const sensor_msgs::PointField& f : cloud.fields)
  {
    if (f.name == name)
    {
      // In 64 bits: offset 4294967295 + 1 wrapped to 0 in 32 and passed, and the state was read
      // from the byte before each point.
      if (f.datatype != sensor_msgs::PointField::UINT8 || std::size_t{ f.offset } + 1 > cloud.point_step)
      {
        return std::string("field ") + name + " must be UINT8 inside point_step";
      }
      offset = f.offset;
      return std::string();
    }
  }
  return std::string("no field ") + name + " (a ray cloud of sl_decoder carries one)";
}
}  // namespace

std::string convertCloud(const sensor_msgs::PointCloud2& cloud, const geometry_msgs::Transform& transform,
                         std::vector<Point>& points)
{
  points.clear();
  FieldReader fx;
  FieldReader fy;
  FieldReader fz;
  FieldReader fc;
  std::string e;
  if (!(e = findField(cloud, "x", true, fx)).empty() || !(e = findField(cloud, "y", true, fy)).empty() ||
      !(e = findField(cloud, "z", true, fz)).empty() || !(e = findField(cloud, "confidence", false, fc)).empty())
  {
    return e;
  }
  const std::size_t width = cloud.width;
  const std::size_t height = cloud.height;
  if (width * height == 0)
  {
    return std::string();
  }
  tf2::Matrix3x3 r;
  tf2::Vector3 t;
  if (!(e = checkLayout(cloud)).empty() || !(e = readTransform(transform, r, t)).empty())
  {
    return e;
  }

  points.resize(width * height);  // keeps the capacity reached by earlier clouds
  std::size_t k = 0;
  for (std::size_t row = 0; row < height; ++row)
  {
    const std::uint8_t* base = cloud.data.data() + row * cloud.row_step;
    for (std::size_t col = 0; col < width; ++col, ++k)
    {
      const std::uint8_t* pt = base + col * cloud.point_step;
      const tf2::Vector3 in(fx.read(pt), fy.read(pt), fz.read(pt));
      const tf2::Vector3 out = r * in + t;
      Point& p = points[k];
      p.x = static_cast<float>(out.x());
      p.y = static_cast<float>(out.y());
      p.z = static_cast<float>(out.z());
      p.confidence = fc.valid() ? static_cast<float>(fc.read(pt)) : 1.0F;
    }
  }
  return std::string();
}
std::string appendRays(const sensor_msgs::PointCloud2& cloud, const geometry_msgs::Transform& transform, bool ray_ends,
                       std::vector<MapRay>& rays)
{
  const char* names[6] = { "x", "y", "z", "sx", "sy", "sz" };
  FieldReader f[6];
  std::string e;
  for (int i = 0; i < 6; ++i)
  {
    if (!(e = findField(cloud, names[i], true, f[i])).empty())
    {
      return e;
    }
  }
  std::size_t state_offset = 0;
  if (ray_ends && !(e = findStateField(cloud, "state", state_offset)).empty())
  {
    return e;
  }
  if (static_cast<std::size_t>(cloud.width) * cloud.height == 0)
  {
    // No points. Checked first: a cloud of width 0 and height 4e9 passes the layout check, and
    // walking its empty rows below took seconds per cloud.
    return std::string();
  }
  tf2::Matrix3x3 r;
  tf2::Vector3 t;
  if (!(e = checkLayout(cloud)).empty() || !(e = readTransform(transform, r, t)).empty())
  {
    return e;
  }
  for (std::size_t row = 0; row < cloud.height; ++row)
  {
    const std::uint8_t* base = cloud.data.data() + row * cloud.row_step;
    for (std::size_t col = 0; col < cloud.width; ++col)
    {
      const std::uint8_t* pt = base + col * cloud.point_step;
      MapRay ray;
      ray.kind = RayKind::Hit;
      if (ray_ends)
      {
        const std::uint8_t state = pt[state_offset];
        if (state == kRayFloor || state == kRayDark)
        {
          ray.kind = RayKind::Free;
        }
        else if (state == kRayLit)
        {
          ray.kind = RayKind::Suspect;
        }
        else
        {
          continue;  // unseen (or decoded, which the points cloud carries): nothing to add
        }
      }
      const tf2::Vector3 end = r * tf2::Vector3(f[0].read(pt), f[1].read(pt), f[2].read(pt)) + t;
      const tf2::Vector3 start = r * tf2::Vector3(f[3].read(pt), f[4].read(pt), f[5].read(pt)) + t;
      if (!std::isfinite(end.x() + end.y() + end.z() + start.x() + start.y() + start.z()))
      {
        continue;
      }
      ray.sx = static_cast<float>(start.x());
      ray.sy = static_cast<float>(start.y());
      ray.sz = static_cast<float>(start.z());
      ray.ex = static_cast<float>(end.x());
      ray.ey = static_cast<float>(end.y());
      ray.ez = static_cast<float>(end.z());
      rays.push_back(ray);
    }
  }
  return std::string();
}

std::string imageRays(const sensor_msgs::PointCloud2& ray_ends, const sensor_msgs::PointCloud2* points,
                      const geometry_msgs::Transform& transform, std::vector<MapRay>& rays, std::string& points_error)
{
  rays.clear();
  points_error.clear();
  const std::string e = appendRays(ray_ends, transform, true, rays);
  if (e.empty() && points != nullptr && points->header.frame_id == ray_ends.header.frame_id)
  {
    points_error = appendRays(*points, transform, false, rays);
  }
  return e;
}

const char* toString(tf2_ros::FilterFailureReason reason)
{
  return reason == tf2_ros::filter_failure_reasons::OutTheBack     ? "older than the tf buffer"
         : reason == tf2_ros::filter_failure_reasons::EmptyFrameID ? "empty frame_id"
                                                                   : "transform unavailable";
}

Pose2D toPose2D(const geometry_msgs::Transform& t)
{
  return Pose2D{ t.translation.x, t.translation.y, tf2::getYaw(t.rotation) };
}
}  // namespace sl_obstacle
