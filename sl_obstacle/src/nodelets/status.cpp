#include "status.h"

#include <limits>

#include "filter_output.h"
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

void fillStatus(const Supervisor& sup, StatusKind kind, const ros::Time& now, const ros::Time& cloud_stamp,
                const ros::Time& map_stamp, const std::string& frame, sl_msgs::ObstacleStatus& s)
{
  s.header.stamp = now;
  s.header.frame_id = frame;
  s.cloud_stamp = sup.haveFrame() ? cloud_stamp : ros::Time();
  s.data_age = sup.haveFrame() ? (now - cloud_stamp).toSec() : std::numeric_limits<double>::infinity();
  s.map_stamp = map_stamp;
  fillCloudStatus(sup.volumeResult(), sup.haveFrame(), s);
  const FrameSummary& f = sup.decisions().frame();
  const bool mapped = sup.world() != nullptr && f.from_map;
  fillMapStatus(f, mapped, mapped ? sup.world()->last().obstacle : 0.0, s);
  if (kind == StatusKind::DECISION)
  {
    fillDecisionStatus(sup.decisions().last(), s);
  }
  else
  {
    fillFilterStatus(sup.filterOutput(), sup.command(), s);
  }
}
}  // namespace sl_obstacle
