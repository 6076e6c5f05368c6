// Cleaning coverage on ROS (~behaviour cover): the coverage grid and its progress as messages, the
// coverage in the navigation status, and the picture of the map with the coverage at the end of a run.
#pragma once

#include <string>

#include <nav_msgs/OccupancyGrid.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>
#include <sl_msgs/NavigationStatus.h>

#include "params.h"
#include "sl_navigation/coverage_planner.h"

namespace sl_navigation
{
/// What a cleaning run publishes besides the navigator's outputs.
class CoverageOutput
{
public:
  /// Advertises coverage (nav_msgs/OccupancyGrid) and coverage_progress (std_msgs/Float32) on @p nh.
  CoverageOutput(ros::NodeHandle& nh, const NodeParams& params);

  /// After the step @p out at @p now: publishes coverage_progress and, while subscribed, coverage
  /// (every map_publish_period each), writes the picture every 30 s and once more when the run is
  /// done (a killed process leaves a recent one), and returns the status:
  /// the coverage, then @p why (no pose) and the navigator's reason (done: SUCCEEDED, mode DONE).
  sl_msgs::NavigationStatus update(const CoverageRunner& runner, const NavOutput& out, const std::string& why,
                                   const ros::Time& now);
  /// The end of the run (shutdown): writes the picture unless the run's end already did.
  void finish(const CoverageRunner& runner, const ros::Time& now);

private:
  /// Writes the map with the coverage to ~coverage_png (nothing when empty); logs errors, and the
  /// @p last picture.
  void writePicture(const CoverageRunner& runner, const ros::Time& now, bool last);

  std::string frame_;
  std::string png_;
  double period_;
  ros::Publisher grid_pub_, progress_pub_;
  ros::Time published_;
  ros::Time written_;  // the last picture
  bool done_ = false;  // the last picture is written
};

/// The coverage as an OccupancyGrid in @p frame: 100 covered, 0 reachable floor not yet covered,
/// -1 elsewhere; the navigation map's cells, cut to the box around the floor and the covered cells.
void toCoverageGrid(const CoverageRunner& runner, const std::string& frame, const ros::Time& stamp,
                    nav_msgs::OccupancyGrid& msg);

/// Writes the navigation map at @p now with the coverage over it (CoverageGrid::toRgb()), cut to its
/// known part and 0.5 m around it, 4 pixels a cell, as an image file (PNG by its name's extension,
/// through OpenCV). @return false, with the reason in @p why, when it cannot be written.
bool writeCoveragePicture(const CoverageRunner& runner, double now, const std::string& path, std::string& why);
}  // namespace sl_navigation
