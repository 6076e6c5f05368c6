#pragma once
/// @file live_procedure.h
/// @brief The steps of the live calibration (ROS-free): which distance comes next, how board and
/// pattern images pair up, what the operator is told, and writing the results.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_calibration/full_calibration.h"
#include "sl_calibration/plane_calibration.h"
#include "sl_decoder/decoder.h"

namespace sl_calibration
{

/**
 * @brief The distances of a plane calibration: the listed ones in order, or the last one the
 * operator gave, which takes precedence until it is captured.
 */
class PlaneSteps
{
public:
  /// @param distances the planned distances, m (may be empty: the operator gives each one)
  explicit PlaneSteps(std::vector<double> distances = {}) : distances_(std::move(distances)) {}

  /// @brief The operator's distance @p d (m), used for the next capture.
  void setDistance(double d) { given_ = d; }

  /// @brief The distance of the next capture: the operator's, else the next listed one.
  /// @return false when there is none
  bool nextDistance(double& d) const;

  /// @brief A capture at @p d is done: the operator's distance is used up; the list advances when
  /// @p d is its next distance.
  void captured(double d);

  /// @brief Captures so far.
  std::size_t views() const { return views_; }

  /// @brief The planned distances.
  const std::vector<double>& distances() const { return distances_; }

  /// @brief True when distances were listed and each of them is captured.
  bool listDone() const { return !distances_.empty() && next_ >= distances_.size(); }

  /// @brief Forgets every capture and the operator's distance.
  void reset();

private:
  std::vector<double> distances_;
  std::size_t next_ = 0;
  std::size_t views_ = 0;
  double given_ = 0.0;
};

/**
 * @brief Collects the images of one capture: a capture waits for a number of images stamped after
 * the settle time, offered by the thread that receives them. Thread-safe.
 */
class FrameCollector
{
public:
  /**
   * @brief Offers an image stamped @p stamp (ns). @p make (the conversion) is called only when a
   * capture wants the image; if it throws, nothing is kept and the exception propagates.
   * @return true when the image was kept
   */
  bool offer(std::int64_t stamp, const std::function<cv::Mat()>& make);

  /**
   * @brief Waits for @p n images stamped at or after @p not_before (ns), at most @p timeout s.
   * @return the images, fewer than @p n on timeout
   */
  std::vector<cv::Mat> collect(int n, std::int64_t not_before, double timeout);

private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  int wanted_ = 0;
  std::int64_t not_before_ = 0;
  std::vector<cv::Mat> frames_;
};

/// @brief Why @p frames cannot be used with a camera of @p width x @p height px ("" when they can).
std::string frameSizeError(const std::vector<cv::Mat>& frames, int width, int height);

/// @brief What one plane capture gave.
struct PlaneCapture
{
  int least = 0;        ///< primitives of the image that gave the fewest
  std::string message;  ///< "<d> m: N primitives per image from K image(s)", with a warning when one gave none
};

/// @brief Decodes @p frames with @p decoder and adds them to @p plane as images at distance @p d (m).
PlaneCapture addPlaneImages(PlaneCalibration& plane, sl_decoder::Decoder& decoder, double d,
                            const std::vector<cv::Mat>& frames);

/**
 * @brief Pairs the board and pattern images of a full calibration: a board image followed by a
 * pattern image is a plane pose; a board image without one is a camera-only view.
 */
class FullSteps
{
public:
  /// @param full the calibration the views go to (outlives this)
  explicit FullSteps(FullCalibration& full) : full_(full) {}

  /// @brief The corners of a board image; a previous board without its pattern image becomes a
  /// camera view. @return the board's number (1, 2, ...)
  int addBoard(const std::vector<cv::Point2f>& corners);

  /// @brief True when the last board image waits for its pattern image.
  bool pendingBoard() const { return pending_; }

  /// @brief The name of the next plane pose ("pose N").
  std::string nextPoseName() const;

  /// @brief The pattern image's @p samples: with the pending board, plane pose @p name.
  /// @throws CalibrationError without a pending board, or as FullCalibration::addPlaneSamples
  void addPattern(const std::string& name, const std::vector<PrimitiveSample>& samples);

  /**
   * @brief The pattern image @p grey of the pending board's pose: decoded and added as the next
   * plane pose. @p name is set to the pose's name. @return the primitives decoded
   * @throws CalibrationError without a pending board, or as FullCalibration::decode and addPlaneSamples
   */
  std::size_t addPatternImage(const cv::Mat& grey, std::string& name);

  /// @brief Before the fit: a pending board becomes a camera view.
  void flush();

  /// @brief Forgets the pending board and the count (the calibration is cleared by its owner).
  void reset();

private:
  FullCalibration& full_;
  bool pending_ = false;
  std::vector<cv::Point2f> pending_corners_;
  int boards_ = 0;
};

/// @brief What a plane calibration asks for next: the distance (with the plane's orientation and
/// where it is measured from, @p options), or another distance or the fit when none is planned.
/// @p captured_distances: distinct distances captured; @p services: the node's namespace.
std::string planePrompt(const PlaneSteps& steps, const PlaneCalibrationOptions& options, std::size_t captured_distances,
                        const std::string& services);

/// @brief What a full calibration asks for next: the pattern image of the pending board's pose,
/// or a board image of a new pose (and the fit once @p min_poses are captured).
std::string fullPrompt(const FullCalibration& full, const FullSteps& steps, int min_poses, const std::string& services);

/// @brief "captured view V[ of N], plane at <capture>": plane capture @p views of @p planned (0: none planned).
std::string capturedViewLine(std::size_t views, std::size_t planned, const std::string& capture);

/// @brief "captured plane pose P of N: K primitives decoded" (" (N needed)" beyond @p min_poses).
std::string capturedPoseLine(int poses, int min_poses, std::size_t primitives);

/// @brief The error of a board image where @p board was not found.
std::string boardNotFoundMessage(const Board& board);

/// @brief What the operator and the log are told after a calibration was written.
struct WrittenCalibration
{
  std::string summary;  ///< the fit's summary, several lines
  std::string message;  ///< one line: the file and the residuals
};

/**
 * @brief Writes a plane calibration: the residuals (@p residuals_file: a plot for a .png name, CSV
 * otherwise, nothing when empty) and then @p rig with the fitted tables to @p output_file.
 * @throws CalibrationError naming a file that cannot be written (the rig is then not written)
 */
WrittenCalibration writePlaneCalibration(const PlaneCalibrationResult& result, const sl_projector::Rig& rig,
                                         const std::string& output_file, const std::string& residuals_file);

/**
 * @brief Writes a full calibration: the residual plot (@p residuals_file, "" none), the camera's
 * camera_info file (@p camera_info_file, "" none) and then the rig to @p output_file.
 */
WrittenCalibration writeFullCalibration(const FullCalibrationResult& result, const std::string& output_file,
                                        const std::string& residuals_file, const std::string& camera_info_file);

/**
 * @brief A live plane calibration: the images of each capture decoded and added at the capture's
 * distance, the distances planned or given, the fit and its files.
 */
class PlaneSession
{
public:
  /**
   * @param rig the rig to start from (its tables are replaced by the fit)
   * @param options the distances' definition and the fit's limits
   * @param distances the planned distances, m (may be empty)
   * @param epipolar_tolerance the decoder's tolerance, px (calibrationDecoderConfig())
   */
  PlaneSession(const sl_projector::Rig& rig, const PlaneCalibrationOptions& options, std::vector<double> distances,
               double epipolar_tolerance);

  /// @brief The distances: the planned one next, the operator's.
  PlaneSteps& steps() { return steps_; }

  /// @brief The images of a capture at @p d (m), decoded and added; the step is done.
  PlaneCapture capture(double d, const std::vector<cv::Mat>& frames);

  /// @brief planePrompt() for this calibration.
  std::string prompt(const std::string& services) const;

  /// @brief Fits and writes (writePlaneCalibration()); nothing is written when the fit fails.
  WrittenCalibration write(const std::string& output_file, const std::string& residuals_file) const;

  /// @brief Forgets every capture.
  void reset();

private:
  sl_projector::Rig rig_;
  PlaneCalibrationOptions options_;
  PlaneCalibration plane_;
  sl_decoder::Decoder decoder_;
  PlaneSteps steps_;
};

/**
 * @brief A live full calibration: board images (camera views, or the first half of a plane pose)
 * and pattern images (the second half), the fit and its files.
 */
class FullSession
{
public:
  /**
   * @param rig the rig to start from
   * @param board the checkerboard
   * @param epipolar_tolerance the decoder's tolerance, px
   * @param min_poses the plane poses needed (>= 3)
   */
  FullSession(const sl_projector::Rig& rig, const Board& board, double epipolar_tolerance, int min_poses);

  /// @brief The calibration (to give a camera model, to count views).
  FullCalibration& calibration() { return full_; }
  /// @brief The pairing of board and pattern images.
  FullSteps& steps() { return steps_; }

  /**
   * @brief A board image @p grey: its corners found and added (FullSteps::addBoard()).
   * @param corners set to the number of corners found
   * @return the board's number, 0 when the board was not found
   */
  int addBoardImage(const cv::Mat& grey, std::size_t& corners);

  /// @brief fullPrompt() for this calibration.
  std::string prompt(const std::string& services) const;

  /// @brief Fits and writes (writeFullCalibration()); a waiting board becomes a camera view first.
  WrittenCalibration write(const std::string& output_file, const std::string& residuals_file,
                           const std::string& camera_info_file);

  /// @brief Forgets every view.
  void reset();

private:
  int min_poses_;
  FullCalibration full_;
  FullSteps steps_;
};

}  // namespace sl_calibration
