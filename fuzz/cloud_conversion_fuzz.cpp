// Fuzz target: sl_obstacle's PointCloud2 conversion (convertCloud, appendRays) on arbitrary
// clouds: fields, offsets, datatypes, point_step, row_step and the data size all come from the
// input, as a misbehaving publisher could send them.
//
// Input: [field count % 9] then per field [name] [datatype] [offset u32] [count]
//   (name % 9 picks x, y, z, confidence, sx, sy, sz, state or "intensity"),
//   [width u32] [height u32] [point_step u32] [row_step u32] [is_bigendian]
//   [transform: 4 signed quaternion bytes / 64, 3 signed translation bytes / 16 m],
//   then the data (the rest of the input). Integers are little-endian.
// Besides the sanitizers it checks that a conversion that succeeds yields width * height points
// and at most that many rays, and inserts the rays into the obstacle node's LocalMap.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/PointCloud2.h>

#include "cloud_conversion.h"
#include "fuzz_input.h"
#include "sl_obstacle/local_map.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  static const char* const kNames[] = { "x", "y", "z", "confidence", "sx", "sy", "sz", "state", "intensity" };
  sl_fuzz::FuzzInput in(data, size);
  sensor_msgs::PointCloud2 cloud;
  const int fields = in.u8() % 9;
  for (int i = 0; i < fields; ++i)
  {
    sensor_msgs::PointField f;
    f.name = kNames[in.u8() % 9];
    f.datatype = in.u8();
    f.offset = in.u32();
    f.count = in.u8();
    cloud.fields.push_back(f);
  }
  cloud.width = in.u32();
  cloud.height = in.u32();
  cloud.point_step = in.u32();
  cloud.row_step = in.u32();
  cloud.is_bigendian = in.u8() & 1;
  geometry_msgs::Transform transform;
  transform.rotation.x = static_cast<int8_t>(in.u8()) / 64.0;
  transform.rotation.y = static_cast<int8_t>(in.u8()) / 64.0;
  transform.rotation.z = static_cast<int8_t>(in.u8()) / 64.0;
  transform.rotation.w = static_cast<int8_t>(in.u8()) / 64.0;
  transform.translation.x = static_cast<int8_t>(in.u8()) / 16.0;
  transform.translation.y = static_cast<int8_t>(in.u8()) / 16.0;
  transform.translation.z = static_cast<int8_t>(in.u8()) / 16.0;
  cloud.data = in.rest();

  const size_t points_in_cloud = static_cast<size_t>(cloud.width) * cloud.height;
  std::vector<sl_obstacle::Point> points;
  if (sl_obstacle::convertCloud(cloud, transform, points).empty())
    FUZZ_CHECK(points.size() == points_in_cloud);

  static sl_obstacle::LocalMap map{ sl_obstacle::MapParams() };  // 1 MB: allocated once, cleared per input
  map.clear();
  for (bool ray_ends : { false, true })
  {
    std::vector<sl_obstacle::MapRay> rays;
    const std::string e = sl_obstacle::appendRays(cloud, transform, ray_ends, rays);
    FUZZ_CHECK(rays.size() <= points_in_cloud);
    if (e.empty())
      map.insert(rays, 1.0);
  }
  return 0;
}
