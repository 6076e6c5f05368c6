#pragma once
/// @file projector_window.h
/// @brief A borderless X11 window that shows a frame pixel for pixel on the projector screen.
/// Private to sl_projector (library sl_projector_device): not installed, not exported.

#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace sl_projector
{

/**
 * @brief Shows a mono8 frame unscaled in an undecorated window at a given position of an X display.
 *
 * The projector is usually a second screen of the X display (for example at x = 1920 right of the
 * laptop panel); the window covers exactly the frame, top-left at (x, y). Not thread-safe: call all
 * methods from one thread.
 */
class ProjectorWindow
{
public:
  ProjectorWindow();
  ~ProjectorWindow();
  ProjectorWindow(const ProjectorWindow&) = delete;
  ProjectorWindow& operator=(const ProjectorWindow&) = delete;

  /**
   * @brief Opens the window on @p display (e.g. ":0"; empty means $DISPLAY) and shows @p frame.
   * @throws std::runtime_error if the display cannot be opened or has an unsupported visual.
   * @throws std::invalid_argument if @p frame is not a non-empty CV_8UC1 image.
   */
  void open(const std::string& display, int x, int y, const cv::Mat& frame);

  /// @brief Replaces the shown frame (same rules as open()).
  void show(const cv::Mat& frame);

  /// @brief Handles pending X events (redraws after exposure); call periodically.
  void spinOnce();

  /// @brief True while a window is open.
  bool isOpen() const;

  /// @brief Closes the window and the display connection.
  void close();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sl_projector
