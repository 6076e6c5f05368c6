#include "cloud_conversion.h"

#include <cstring>
#include <limits>

#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>

namespace sl_obstacle
{
namespace
{
struct FieldReader
{
  int offset = -1;
  std::uint8_t datatype = 0;

  bool valid() const { return offset >= 0; }

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
    reader.offset = static_cast<int>(f.offset);
    reader.datatype = f.datatype;
    return std::string();
  }
  return required ? std::string("no field ") + name : std::string();
}
}  // namespace

std::string convertCloud(const sensor_msgs::PointCloud2& cloud, const geometry_msgs::Transform& transform,
                         std::vector<Point>& points)
{
  points.clear();
  if (cloud.is_bigendian)
  {
    return "big-endian clouds are not supported";
  }
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
  if (cloud.point_step == 0 || cloud.row_step < width * cloud.point_step ||
      cloud.data.size() < (height - 1) * cloud.row_step + width * cloud.point_step)
  {
    return "data size does not match width, height, point_step and row_step";
  }

  const tf2::Quaternion q(transform.rotation.x, transform.rotation.y, transform.rotation.z, transform.rotation.w);
  if (!(q.length2() > 0.5))
  {
    return "transform has an invalid rotation";
  }
  const tf2::Matrix3x3 r(q.normalized());
  const tf2::Vector3 t(transform.translation.x, transform.translation.y, transform.translation.z);

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
}  // namespace sl_obstacle
