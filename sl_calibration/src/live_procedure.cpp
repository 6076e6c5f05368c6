#include "sl_calibration/live_procedure.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include "sl_calibration/camera_calibration.h"
#include "sl_calibration/common.h"
#include "sl_calibration/residual_plot.h"

namespace sl_calibration
{

bool FrameCollector::offer(std::int64_t stamp, const std::function<cv::Mat()>& make)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (wanted_ <= 0 || stamp < not_before_)
    return false;
  frames_.push_back(make());
  --wanted_;
  arrived_.notify_all();
  return true;
}

std::vector<cv::Mat> FrameCollector::collect(int n, std::int64_t not_before, double timeout)
{
  std::unique_lock<std::mutex> lock(mutex_);
  frames_.clear();
  wanted_ = n;
  not_before_ = not_before;
  arrived_.wait_for(lock, std::chrono::duration<double>(timeout), [this] { return wanted_ <= 0; });
  wanted_ = 0;
  std::vector<cv::Mat> frames;
  frames.swap(frames_);
  return frames;
}

std::string frameSizeError(const std::vector<cv::Mat>& frames, int width, int height)
{
  for (const cv::Mat& f : frames)
    if (f.cols != width || f.rows != height)
      return "the images are " + std::to_string(f.cols) + " x " + std::to_string(f.rows) + " px, the rig's camera " +
             std::to_string(width) + " x " + std::to_string(height);
  return std::string();
}

PlaneCapture addPlaneImages(PlaneCalibration& plane, sl_decoder::Decoder& decoder, double d,
                            const std::vector<cv::Mat>& frames)
{
  int total = 0, least = frames.empty() ? 0 : 1 << 30;
  sl_decoder::DecodeResult result;
  for (size_t i = 0; i < frames.size(); ++i)
  {
    decoder.decode(frames[i], result);
    const int n = plane.addImage(d, result, "image " + std::to_string(i) + " at " + fixed(d, 3) + " m");
    total += n;
    least = std::min(least, n);
  }
  std::ostringstream o;
  o << fixed(d, 3) << " m: " << total / std::max(1, static_cast<int>(frames.size())) << " primitives per image from "
    << frames.size() << " image(s)";
  if (least == 0)
    o << " (WARNING: an image decoded nothing: projector off, plane out of view, or the wrong rig file?)";
  return { least, o.str() };
}

bool PlaneSteps::nextDistance(double& d) const
{
  if (given_ > 0.0)
  {
    d = given_;
    return true;
  }
  if (next_ < distances_.size())
  {
    d = distances_[next_];
    return true;
  }
  return false;
}

void PlaneSteps::captured(double d)
{
  given_ = 0.0;
  if (next_ < distances_.size() && std::abs(distances_[next_] - d) < 1e-9)
    ++next_;
  ++views_;
}

void PlaneSteps::reset()
{
  next_ = 0;
  views_ = 0;
  given_ = 0.0;
}

int FullSteps::addBoard(const std::vector<cv::Point2f>& corners)
{
  ++boards_;
  if (pending_)  // the previous board image had no pattern image: a camera view
    full_.addCameraCorners("board " + std::to_string(boards_ - 1), pending_corners_);
  pending_corners_ = corners;
  pending_ = true;
  return boards_;
}

std::string FullSteps::nextPoseName() const
{
  return "pose " + std::to_string(full_.planeViews() + 1);
}

void FullSteps::addPattern(const std::string& name, const std::vector<PrimitiveSample>& samples)
{
  if (!pending_)
    throw CalibrationError(name + ": no board image of this pose to pair the pattern image with");
  full_.addPlaneSamples(name, pending_corners_, samples);
  pending_ = false;
}

std::size_t FullSteps::addPatternImage(const cv::Mat& grey, std::string& name)
{
  name = nextPoseName();
  if (!pending_)
    throw CalibrationError(name + ": no board image of this pose to pair the pattern image with");
  const std::vector<PrimitiveSample> samples = full_.decode(name, grey);
  addPattern(name, samples);
  return samples.size();
}

void FullSteps::flush()
{
  if (!pending_)
    return;
  full_.addCameraCorners("board " + std::to_string(boards_), pending_corners_);
  pending_ = false;
}

void FullSteps::reset()
{
  pending_ = false;
  pending_corners_.clear();
  boards_ = 0;
}

std::string planePrompt(const PlaneSteps& steps, const PlaneCalibrationOptions& options, std::size_t captured_distances,
                        const std::string& services)
{
  std::ostringstream o;
  double d;
  if (steps.nextDistance(d))
    o << "plane calibration: put the plane at " << fixed(d, 3) << " m ("
      << (options.normal == PlaneNormal::Camera ? "perpendicular to the camera's optical axis"
                                                : "perpendicular to the robot's x axis")
      << ", measured from the "
      << (options.reference == DistanceReference::Camera ? "camera's optical centre" : "robot's front edge")
      << "), then: rosservice call " << services << "/capture";
  else
    o << "plane calibration: " << captured_distances << " distance(s) captured; publish the next distance (m) on "
      << services << "/distance and call " << services << "/capture, or call " << services << "/calibrate";
  return o.str();
}

std::string fullPrompt(const FullCalibration& full, const FullSteps& steps, int min_poses, const std::string& services)
{
  std::ostringstream o;
  o << "full calibration: " << full.planeViews() << " plane pose(s) of >= " << min_poses << ", " << full.boardViews()
    << " board view(s). ";
  if (steps.pendingBoard())
    o << "Now the pattern image of the same pose: projector on, board covered, lights dimmed; then: rosservice call "
      << services << "/capture_pattern (or capture_board again to keep the last board as a camera view)";
  else
    o << "Put the plane (board " << full.board().cols << "x" << full.board().rows << " inner corners) in a new pose, "
      << "lights on and projector dark; then: rosservice call " << services << "/capture_board"
      << (full.planeViews() >= min_poses ? " (or " + services + "/calibrate)" : std::string());
  return o.str();
}

std::string capturedViewLine(std::size_t views, std::size_t planned, const std::string& capture)
{
  return "captured view " + std::to_string(views) +
         (views <= planned ? " of " + std::to_string(planned) : std::string()) + ", plane at " + capture;
}

std::string capturedPoseLine(int poses, int min_poses, std::size_t primitives)
{
  return "captured plane pose " + std::to_string(poses) +
         (poses <= min_poses ? " of " + std::to_string(min_poses) : " (" + std::to_string(min_poses) + " needed)") +
         ": " + std::to_string(primitives) + " primitives decoded";
}

std::string boardNotFoundMessage(const Board& board)
{
  return "checkerboard of " + std::to_string(board.cols) + "x" + std::to_string(board.rows) +
         " inner corners not found in the image (the whole board must be visible, lit and in focus)";
}

WrittenCalibration writePlaneCalibration(const PlaneCalibrationResult& r, const sl_projector::Rig& rig,
                                         const std::string& output_file, const std::string& residuals_file)
{
  if (isPngPath(residuals_file))
    writePlaneResidualPlot(residuals_file, r, cv::Size(rig.camera.width, rig.camera.height));
  else if (!residuals_file.empty())
  {
    std::ofstream csv(residuals_file);
    if (!csv || !(csv << r.residualsCsv()))
      throw CalibrationError(residuals_file + ": cannot write the residuals");
  }
  sl_projector::saveRig(withTables(rig, r), output_file);
  return { "plane calibration:\n" + r.summary(), "wrote " + output_file + ": " + std::to_string(r.calibrated) +
                                                     " primitives calibrated, rms " +
                                                     fixed(1000.0 * r.rational_rms, 3) + " mm (rational), " +
                                                     fixed(1000.0 * r.linear_rms, 3) + " mm (linear)" };
}

WrittenCalibration writeFullCalibration(const FullCalibrationResult& r, const std::string& output_file,
                                        const std::string& residuals_file, const std::string& camera_info_file)
{
  if (!residuals_file.empty())
    writeCameraResidualPlot(residuals_file, r);
  if (!camera_info_file.empty())
    saveCameraInfo(r.rig.camera, camera_info_file);
  sl_projector::saveRig(r.rig, output_file);
  return { "full calibration:\n" + r.summary(), "wrote " + output_file + ": camera " + fixed(r.camera.rms, 3) +
                                                    " px, projector " + fixed(r.projector.rms, 3) +
                                                    " px rms reprojection error" };
}

PlaneSession::PlaneSession(const sl_projector::Rig& rig, const PlaneCalibrationOptions& options,
                           std::vector<double> distances, double epipolar_tolerance)
  : rig_(rig),
    options_(options),
    plane_(rig, options),
    decoder_(rig, calibrationDecoderConfig(epipolar_tolerance)),
    steps_(std::move(distances))
{
}

PlaneCapture PlaneSession::capture(double d, const std::vector<cv::Mat>& frames)
{
  PlaneCapture c = addPlaneImages(plane_, decoder_, d, frames);
  steps_.captured(d);
  return c;
}

std::string PlaneSession::prompt(const std::string& services) const
{
  return planePrompt(steps_, options_, plane_.distances().size(), services);
}

WrittenCalibration PlaneSession::write(const std::string& output_file, const std::string& residuals_file) const
{
  return writePlaneCalibration(plane_.fit(), rig_, output_file, residuals_file);
}

void PlaneSession::reset()
{
  plane_.clear();
  steps_.reset();
}

namespace
{
FullCalibrationOptions fullOptions(double epipolar_tolerance, int min_poses)
{
  FullCalibrationOptions options;
  options.epipolar_tolerance = epipolar_tolerance;
  options.projector.min_views = min_poses;
  return options;
}
}  // namespace

FullSession::FullSession(const sl_projector::Rig& rig, const Board& board, double epipolar_tolerance, int min_poses)
  : min_poses_(min_poses), full_(rig, board, fullOptions(epipolar_tolerance, min_poses)), steps_(full_)
{
}

int FullSession::addBoardImage(const cv::Mat& grey, std::size_t& corners)
{
  std::vector<cv::Point2f> found;
  corners = 0;
  if (!findBoardCorners(grey, full_.board(), found))
    return 0;
  corners = found.size();
  return steps_.addBoard(found);
}

std::string FullSession::prompt(const std::string& services) const
{
  return fullPrompt(full_, steps_, min_poses_, services);
}

WrittenCalibration FullSession::write(const std::string& output_file, const std::string& residuals_file,
                                      const std::string& camera_info_file)
{
  steps_.flush();
  return writeFullCalibration(full_.calibrate(), output_file, residuals_file, camera_info_file);
}

void FullSession::reset()
{
  full_.clear();
  steps_.reset();
}

}  // namespace sl_calibration
