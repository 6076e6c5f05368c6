#include "clouds.h"

#include <cstring>
#include <limits>

#include <boost/make_shared.hpp>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "sl_msgs/ray_ends.h"

namespace sl_decoder
{
// The core's ray states are the wire values of the ray_ends cloud.
static_assert(static_cast<int>(RayState::Decoded) == sl_msgs::ray_ends::DECODED, "RayState::Decoded");
static_assert(static_cast<int>(RayState::Floor) == sl_msgs::ray_ends::FLOOR, "RayState::Floor");
static_assert(static_cast<int>(RayState::Dark) == sl_msgs::ray_ends::DARK, "RayState::Dark");
static_assert(static_cast<int>(RayState::Lit) == sl_msgs::ray_ends::LIT, "RayState::Lit");
static_assert(static_cast<int>(RayState::Unseen) == sl_msgs::ray_ends::UNSEEN, "RayState::Unseen");

namespace
{
/// Fills an organized cloud of @p rows x @p cols with NaN points, each with its row and column.
void fillOrganized(sensor_msgs::PointCloud2& cloud, int rows, int cols)
{
  cloud.height = static_cast<uint32_t>(rows);
  cloud.width = static_cast<uint32_t>(cols);
  cloud.row_step = cloud.width * cloud.point_step;
  cloud.is_dense = false;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), cf(cloud, "confidence"), u(cloud, "u"), sx(cloud, "sx");
  sensor_msgs::PointCloud2Iterator<uint16_t> r(cloud, "row");
  for (int i = 0; i < rows * cols; ++i, ++x, ++cf, ++u, ++r, ++sx)
  {
    x[0] = x[1] = x[2] = nan;
    sx[0] = sx[1] = sx[2] = nan;
    cf[0] = 0.f;
    u[0] = u[1] = nan;
    r[0] = static_cast<uint16_t>(i / cols);
    r[1] = static_cast<uint16_t>(i % cols);
  }
}
}  // namespace

sensor_msgs::PointCloud2Ptr toPointsCloud(const DecodeResult& result, const Eigen::Isometry3d& to_target,
                                          const Eigen::Vector3d& projector_centre, int rows, int cols, bool organized,
                                          const std_msgs::Header& header)
{
  // Published by pointer: nodelets in the same manager receive it without a copy.
  const sensor_msgs::PointCloud2Ptr cloud_ptr = boost::make_shared<sensor_msgs::PointCloud2>();
  sensor_msgs::PointCloud2& cloud = *cloud_ptr;
  cloud.header = header;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  using sensor_msgs::PointField;
  modifier.setPointCloud2Fields(
      11, "x", 1, PointField::FLOAT32, "y", 1, PointField::FLOAT32, "z", 1, PointField::FLOAT32, "confidence", 1,
      PointField::FLOAT32, "row", 1, PointField::UINT16, "col", 1, PointField::UINT16, "u", 1, PointField::FLOAT32, "v",
      1, PointField::FLOAT32, "sx", 1, PointField::FLOAT32, "sy", 1, PointField::FLOAT32, "sz", 1, PointField::FLOAT32);
  const Eigen::Vector3d centre = to_target * projector_centre;
  if (organized)
  {
    modifier.resize(static_cast<size_t>(rows * cols));
    fillOrganized(cloud, rows, cols);
  }
  else
  {
    modifier.resize(static_cast<size_t>(result.valid));
    cloud.is_dense = true;
  }
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), cf(cloud, "confidence"), u(cloud, "u"), sx(cloud, "sx");
  sensor_msgs::PointCloud2Iterator<uint16_t> r(cloud, "row");
  size_t k = 0;
  for (const Blob& b : result.blobs)
  {
    if (!b.valid)
      continue;
    const int index = static_cast<int>(organized ? static_cast<size_t>(b.row * cols + b.col) : k++);
    const Eigen::Vector3d p = to_target * Eigen::Vector3d(b.x, b.y, b.z);
    sensor_msgs::PointCloud2Iterator<float> xi = x + index, ci = cf + index, ui = u + index, si = sx + index;
    sensor_msgs::PointCloud2Iterator<uint16_t> ri = r + index;
    xi[0] = static_cast<float>(p.x());
    xi[1] = static_cast<float>(p.y());
    xi[2] = static_cast<float>(p.z());
    ci[0] = b.confidence;
    ri[0] = static_cast<uint16_t>(b.row);
    ri[1] = static_cast<uint16_t>(b.col);
    ui[0] = b.u;
    ui[1] = b.v;
    si[0] = static_cast<float>(centre.x());
    si[1] = static_cast<float>(centre.y());
    si[2] = static_cast<float>(centre.z());
  }
  return cloud_ptr;
}

sensor_msgs::PointCloud2Ptr toRayEndsCloud(const std::vector<RayOutcome>& outcomes, int decoded,
                                           const Eigen::Isometry3d& to_target, int cols, const std_msgs::Header& header)
{
  const sensor_msgs::PointCloud2Ptr cloud_ptr = boost::make_shared<sensor_msgs::PointCloud2>();
  sensor_msgs::PointCloud2& cloud = *cloud_ptr;
  cloud.header = header;
  // The layout of sl_msgs/ray_ends.h: 6 floats, the state, the pattern row and column.
  namespace re = sl_msgs::ray_ends;
  auto field = [&cloud](const char* name, uint32_t offset, uint8_t type)
  {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    cloud.fields.push_back(f);
  };
  const char* names[6] = { "x", "y", "z", "sx", "sy", "sz" };
  for (uint32_t k = 0; k < 6; ++k)
    field(names[k], 4 * k, sensor_msgs::PointField::FLOAT32);
  field("state", re::kStateOffset, sensor_msgs::PointField::UINT8);
  field("row", re::kRowOffset, sensor_msgs::PointField::UINT16);
  field("col", re::kColOffset, sensor_msgs::PointField::UINT16);
  cloud.point_step = re::kPointStep;
  const size_t n = outcomes.size();
  const size_t count = n - static_cast<size_t>(decoded);
  cloud.height = 1;
  cloud.width = static_cast<uint32_t>(count);
  cloud.row_step = cloud.width * cloud.point_step;
  cloud.is_dense = false;  // unseen rays are NaN
  cloud.data.assign(count * cloud.point_step, 0);
  uint8_t* out = cloud.data.data();
  for (size_t i = 0; i < n; ++i)
  {
    const RayOutcome& o = outcomes[i];
    if (o.state == RayState::Decoded)
      continue;
    const Eigen::Vector3f end = (to_target * o.end.cast<double>()).cast<float>();
    const Eigen::Vector3f start = (to_target * o.start.cast<double>()).cast<float>();
    re::Point point{};
    point.x = end.x();
    point.y = end.y();
    point.z = end.z();
    point.sx = start.x();
    point.sy = start.y();
    point.sz = start.z();
    point.state = static_cast<uint8_t>(o.state);
    point.row = static_cast<uint16_t>(i / static_cast<size_t>(cols));
    point.col = static_cast<uint16_t>(i % static_cast<size_t>(cols));
    std::memcpy(out, &point, sizeof(point));
    out += cloud.point_step;
  }
  return cloud_ptr;
}
}  // namespace sl_decoder
