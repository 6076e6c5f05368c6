// The structured-light sensor the sl_obstacle tests imitate: 16 x 64 dots whose rays cover the
// 331 x 173 mm window at 675 mm (used by the gtests' synthetic clouds and the fake_wall_cloud node).
#pragma once

namespace sl_obstacle
{
namespace test
{
/// The imitated sensor: rays from @p origin through a grid of rows x cols points that fill the window
/// W x H at x = focus_x.
struct SensorModel
{
  double origin_x = -0.10;
  double origin_y = 0.0;
  double origin_z = 0.0865;
  double focus_x = 0.675;
  double width = 0.331;
  double height = 0.173;
  int rows = 16;
  int cols = 64;
  double max_distance = 3.0;  ///< along the ray; no hit beyond
};
}  // namespace test
}  // namespace sl_obstacle
