// What rviz shows of the obstacle node: the working volume, what the check found in it, the
// filtered command's footprint, and the local map as an occupancy grid.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>
#include <nav_msgs/OccupancyGrid.h>
#include <visualization_msgs/MarkerArray.h>

#include "params.h"
#include "sl_obstacle/point.h"
#include "sl_obstacle/supervisor.h"
#include "sl_obstacle/volume_checker.h"
#include "sl_obstacle/working_volume.h"

namespace sl_obstacle
{
/// Fills @p out with six markers in @p frame at @p stamp: [0] the box of @p v (red when @p blocked,
/// green otherwise), [1] the nearest obstacle point, [2] the accepted obstacle points and [3] the
/// in-box points rejected as noise (of @p points, as @p r indexes them), [4] the free distance of
/// each sector on the floor; [5] is left for the caller (the safety filter's footprint), with the
/// common header fields set.
void volumeMarkers(const VolumeResult& r, const WorkingVolume& v, const std::vector<Point>& points, bool blocked,
                   const std::string& frame, const ros::Time& stamp, visualization_msgs::MarkerArray& out);

/// Turns POINTS markers without points into DELETE (rviz draws nothing for them then).
void deleteEmptyPointMarkers(visualization_msgs::MarkerArray& markers);

/// All markers of the obstacle node: volumeMarkers() of the newest cloud's @p points (in
/// @p volume_frame at @p stamp; red when sup.blocked()) and [5] the footprint the filtered command
/// sweeps (in @p map_frame at @p now; deleted unless outside commands command and the pose is known).
void obstacleMarkers(const Supervisor& sup, const std::vector<Point>& points, const Settings& settings,
                     const std::string& volume_frame, const std::string& map_frame, const ros::Time& stamp,
                     const ros::Time& now, visualization_msgs::MarkerArray& out);

/// The local map @p map at @p now as an occupancy grid of cells of @p resolution (m) in @p frame.
void localMapGrid(const LocalMap& map, double resolution, const std::string& frame, const ros::Time& now,
                  nav_msgs::OccupancyGrid& grid);

/// Publishes `markers` and, with the map, `local_map` (at most 2 Hz), each only while subscribed.
class Display
{
public:
  /// Advertises in @p nh; @p params must outlive this.
  Display(ros::NodeHandle& nh, const NodeletParams& params, bool map);
  /// The markers of the newest cloud's @p points, captured at @p stamp (obstacleMarkers()).
  void showCloud(const Supervisor& sup, const std::vector<Point>& points, const ros::Time& stamp);
  /// The local map at @p now, while the robot's pose is known.
  void showMap(const Supervisor& sup, const ros::Time& now);

private:
  const NodeletParams& params_;
  ros::Publisher markers_pub_;
  ros::Publisher map_pub_;
  visualization_msgs::MarkerArray markers_;
  nav_msgs::OccupancyGrid grid_;
  ros::Time map_published_;
};
}  // namespace sl_obstacle
