#include "status.h"

#include <limits>

#include "status_codes.h"  // the enums copied here equal the message constants

namespace sl_obstacle
{
void fillCloudStatus(const VolumeResult& r, bool have_frame, sl_msgs::ObstacleStatus& s)
{
  s.nearest_distance = have_frame ? r.nearest_distance : std::numeric_limits<double>::infinity();
  s.nearest_point.x = r.nearest_point.x;
  s.nearest_point.y = r.nearest_point.y;
  s.nearest_point.z = r.nearest_point.z;
  s.free_distance = have_frame ? r.free_distance : 0.0;
  s.sector_free_distance.resize(r.sectors.size());
  for (std::size_t i = 0; i < r.sectors.size(); ++i)
  {
    s.sector_free_distance[i] = have_frame ? static_cast<float>(r.sectors[i].free_distance) : 0.0F;
  }
  s.points_in_box = r.in_box_points;
  s.obstacle_points = r.obstacle_points;
  s.invalid_points = r.invalid_points;
  s.coverage = static_cast<float>(have_frame ? r.coverage : 0.0);
}

void fillMapStatus(const FrameSummary& f, bool mapped, double map_obstacle, sl_msgs::ObstacleStatus& s)
{
  s.map_free_distance = mapped ? f.free_distance : 0.0;
  s.map_obstacle_distance = mapped ? map_obstacle : std::numeric_limits<double>::infinity();
  s.map_known_fraction = static_cast<float>(mapped ? f.coverage : 0.0);
  s.reverse_free_distance = mapped ? f.reverse_free : 0.0;
  s.best_turn = mapped ? f.best_turn : 0.0;
}

void fillDecisionStatus(const Decision& d, sl_msgs::ObstacleStatus& s)
{
  s.state = static_cast<uint8_t>(d.state);
  s.reason_code = static_cast<uint8_t>(d.reason);
  s.reason = d.text;
  s.blocked = d.blocked;
  s.teleop = false;
  s.input_linear = s.input_angular = 0.0;
  s.command_scale = 1.0;
  s.command = static_cast<uint8_t>(d.command);
  s.command_distance = d.distance;
  s.command_speed = d.speed;
  s.command_angular_speed = d.angular_speed;
}
}  // namespace sl_obstacle
