#include "coverage_output.h"

#include <algorithm>
#include <exception>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <ros/console.h>
#include <std_msgs/Float32.h>

#include "conversions.h"

namespace sl_navigation
{
namespace
{
constexpr double kPictureInterval = 30.0;  // s between pictures while cleaning
}  // namespace

CoverageOutput::CoverageOutput(ros::NodeHandle& nh, const NodeParams& params)
  : frame_(params.odom_frame), png_(params.coverage_png), period_(params.map_publish_period)
{
  grid_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("coverage", 1);
  progress_pub_ = nh.advertise<std_msgs::Float32>("coverage_progress", 1);
}

sl_msgs::NavigationStatus CoverageOutput::update(const CoverageRunner& runner, const NavOutput& out,
                                                 const std::string& why, const ros::Time& now)
{
  const NavGoal& goal = runner.navigator().goal();
  sl_msgs::NavigationStatus status =
      toStatus(out, toPoseStamped(Pose{ goal.x, goal.y, goal.yaw }, frame_, now), frame_, now);
  if (!why.empty())
  {
    status.reason = why + (status.reason.empty() ? "" : "; " + status.reason);
  }
  if (runner.done())
  {
    status.state = sl_msgs::NavigationStatus::SUCCEEDED;
    status.mode = "DONE";
  }
  status.reason = runner.summary() + (status.reason.empty() ? "" : "; " + status.reason);
  if (runner.done() && !done_)
  {
    ROS_INFO("navigation: cleaning done: %s", runner.summary().c_str());
    done_ = true;
    writePicture(runner, now, true);
  }
  else if (!done_ && (now - written_).toSec() >= kPictureInterval)
  {
    writePicture(runner, now, false);  // a recent picture also when the process is killed
  }
  if ((now - published_).toSec() >= period_)
  {
    published_ = now;
    std_msgs::Float32 progress;
    progress.data = static_cast<float>(runner.progress());
    progress_pub_.publish(progress);
    if (grid_pub_.getNumSubscribers() > 0)
    {
      nav_msgs::OccupancyGrid grid;
      toCoverageGrid(runner, frame_, now, grid);
      grid_pub_.publish(grid);
    }
  }
  return status;
}

void CoverageOutput::finish(const CoverageRunner& runner, const ros::Time& now)
{
  if (!done_)
  {
    ROS_INFO("navigation: %s ends: %s", runner.planner().params().roam ? "roaming" : "cleaning",
             runner.summary().c_str());
    done_ = true;
    writePicture(runner, now, true);
  }
}

void CoverageOutput::writePicture(const CoverageRunner& runner, const ros::Time& now, bool last)
{
  written_ = now;
  if (png_.empty())
  {
    return;
  }
  std::string why;
  if (!writeCoveragePicture(runner, now.toSec(), png_, why))
  {
    ROS_ERROR_THROTTLE(60.0, "navigation: cannot write ~coverage_png '%s': %s", png_.c_str(), why.c_str());
  }
  else if (last)
  {
    ROS_INFO("navigation: map and coverage written to %s (~coverage_png)", png_.c_str());
  }
}

void toCoverageGrid(const CoverageRunner& runner, const std::string& frame, const ros::Time& stamp,
                    nav_msgs::OccupancyGrid& msg)
{
  const NavGrid& grid = runner.navigator().grid();
  std::vector<std::int8_t> all;
  runner.coverage().toOccupancy(runner.planner().floor(), all);
  // Only the box around the floor and the covered cells: rviz draws the rest (-1) opaque.
  const int n = runner.coverage().width();
  int x0 = n, x1 = 0, y0 = n, y1 = 0;
  for (int iy = 0; iy < n; ++iy)
  {
    for (int ix = 0; ix < n; ++ix)
    {
      if (all[static_cast<std::size_t>(iy) * n + ix] >= 0)
      {
        x0 = std::min(x0, ix), x1 = std::max(x1, ix), y0 = std::min(y0, iy), y1 = std::max(y1, iy);
      }
    }
  }
  if (x0 > x1)
  {
    x0 = x1 = y0 = y1 = n / 2;  // nothing yet: one unknown cell in the middle
  }
  const double res = grid.params().resolution;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame;
  msg.info.map_load_time = stamp;
  msg.info.resolution = static_cast<float>(res);
  msg.info.width = static_cast<unsigned>(x1 - x0 + 1);
  msg.info.height = static_cast<unsigned>(y1 - y0 + 1);
  msg.info.origin.position.x = grid.originX() + x0 * res;
  msg.info.origin.position.y = grid.originY() + y0 * res;
  msg.info.origin.orientation.w = 1.0;
  msg.data.clear();
  msg.data.reserve(static_cast<std::size_t>(msg.info.width) * msg.info.height);
  for (int iy = y0; iy <= y1; ++iy)
  {
    const auto row = all.begin() + static_cast<std::ptrdiff_t>(iy) * n;
    msg.data.insert(msg.data.end(), row + x0, row + x1 + 1);
  }
}

bool writeCoveragePicture(const CoverageRunner& runner, double now, const std::string& path, std::string& why)
{
  const NavGrid& grid = runner.navigator().grid();
  std::vector<std::uint8_t> rgb;
  runner.coverage().toRgb(grid, now, runner.planner().floor(), rgb);
  const int n = runner.coverage().width();
  if (n <= 0 || rgb.size() != static_cast<std::size_t>(n) * n * 3)
  {
    why = "the coverage has no picture (no map yet)";
    return false;
  }
  // The known part of the map (toRgb() is top row first) with 0.5 m around it, 4 pixels a cell.
  int x0 = n, x1 = -1, y0 = n, y1 = -1;
  for (int iy = 0; iy < n; ++iy)
  {
    for (int ix = 0; ix < n; ++ix)
    {
      if (grid.cell(ix, iy, now) != Cell::Unknown)
      {
        x0 = std::min(x0, ix), x1 = std::max(x1, ix), y0 = std::min(y0, iy), y1 = std::max(y1, iy);
      }
    }
  }
  const int margin = static_cast<int>(0.5 / grid.params().resolution);
  const cv::Rect known =
      x1 < 0 ? cv::Rect(0, 0, n, n)
             : cv::Rect(x0 - margin, n - 1 - y1 - margin, x1 - x0 + 1 + 2 * margin, y1 - y0 + 1 + 2 * margin) &
                   cv::Rect(0, 0, n, n);
  try
  {
    const cv::Mat image(n, n, CV_8UC3, rgb.data());
    cv::Mat bgr, large;
    cv::cvtColor(image(known), bgr, cv::COLOR_RGB2BGR);
    cv::resize(bgr, large, cv::Size(), 4.0, 4.0, cv::INTER_NEAREST);
    if (cv::imwrite(path, large))
    {
      return true;
    }
    why = "OpenCV could not write the file (folder missing or not writable, or an unknown extension)";
  }
  catch (const std::exception& e)
  {
    why = e.what();
  }
  return false;
}
}  // namespace sl_navigation
