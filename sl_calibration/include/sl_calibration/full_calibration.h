#pragma once
/// @file full_calibration.h
/// @brief Full projector-camera calibration (Zhang's method for the camera, the projector as an
/// inverse camera): collects checkerboard views and decoded pattern views of calibration planes and
/// produces the rig's camera, projector and projector pose (ROS-free).

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_calibration/camera_calibration.h"
#include "sl_calibration/lens_blur.h"
#include "sl_calibration/plane_calibration.h"
#include "sl_calibration/projector_calibration.h"
#include "sl_decoder/decoder.h"

namespace sl_calibration
{

/// @brief Options of the full calibration.
struct FullCalibrationOptions
{
  CameraCalibrationOptions camera;                            ///< camera fit
  ProjectorCalibrationOptions projector;                      ///< projector fit
  PlaneCalibrationOptions distance_planes;                    ///< how known distances define planes (reference, normal)
  double epipolar_tolerance = kCalibrationEpipolarTolerance;  ///< decoder tolerance for the pattern images, px
  /// After the separate fits, refine everything together (bundle adjustment): camera and projector
  /// models, projector pose and board poses, minimising the checkerboard corners' reprojection error
  /// in the camera and the primitives' reprojection error in the projector.
  bool joint_refinement = true;
  int max_iterations = 50;  ///< Levenberg-Marquardt iterations of the joint refinement
};

/// @brief Everything the full calibration produced.
struct FullCalibrationResult
{
  bool camera_calibrated = false;         ///< false when the camera model was given (setCamera())
  CameraCalibrationResult camera;         ///< camera fit (model also set when given)
  std::vector<std::string> camera_views;  ///< names of the board views, in the order of camera.view_rms
  ProjectorCalibrationResult projector;   ///< projector fit
  bool refined = false;                   ///< the joint refinement ran (the numbers above are after it)
  std::vector<std::string> plane_views;   ///< names of the plane views, in the order of projector.view_rms
  /// The camera lens's focus distance and f-number from the blur of the board edges at their depths
  /// (board images only); when valid, written into rig.camera_optics.
  LensFit camera_lens;
  sl_projector::Rig rig;  ///< the input rig with camera, projector and projector_pose replaced
  /// The camera's reprojection residuals of every board corner (projected minus found, px) with the
  /// final camera model and board poses; `view` indexes camera_views.
  std::vector<ImageResidual> camera_residuals;

  /// @brief A human-readable report: models, reprojection errors per view, pose.
  std::string summary() const;
};

/**
 * @brief Collects the views of a full calibration and runs it.
 *
 * Camera views are checkerboard images (lights on, projector dark). A plane view is one pose of a
 * calibration plane seen twice: a checkerboard image (gives the plane through the board pose) and
 * a pattern image (the projector on, the board covered or outside the pattern); or a pattern image
 * of a plane perpendicular to the robot at a known distance (the plane calibration's set-up). The
 * board images of plane views count as camera views too.
 */
class FullCalibration
{
public:
  /**
   * @param rig the nominal rig: pattern, mount, projector frame size and the initial geometry the
   *        decoder uses to find the pattern (it need only be roughly right).
   * @param board the checkerboard (inner corners, square size).
   * @throws std::invalid_argument for an invalid board, rig or options.
   */
  FullCalibration(const sl_projector::Rig& rig, const Board& board,
                  const FullCalibrationOptions& options = FullCalibrationOptions());
  ~FullCalibration();

  /// @brief Uses a known camera model (e.g. from ROS camera_calibration) instead of calibrating it.
  void setCamera(const sl_projector::PinholeModel& camera);

  /**
   * @brief Adds a checkerboard image for the camera intrinsics.
   * @throws CalibrationError naming @p name if the board is not found or the size is wrong.
   */
  void addCameraView(const std::string& name, const cv::Mat& grey);

  /**
   * @brief Adds a plane pose: the checkerboard image and the pattern image of the same pose.
   * @throws CalibrationError naming the image if the board is not found or too few primitives decode.
   */
  void addPlaneView(const std::string& board_name, const cv::Mat& board_grey, const std::string& pattern_name,
                    const cv::Mat& pattern_grey);

  /**
   * @brief Adds the pattern image of a plane perpendicular to the robot at a known distance (m),
   * as defined by options.distance_planes (see planeAtDistance()).
   * @throws CalibrationError naming the image if too few primitives decode.
   */
  void addDistanceView(const std::string& pattern_name, const cv::Mat& pattern_grey, double distance);

  /// @brief Lower-level: a board view from corners already found.
  void addCameraCorners(const std::string& name, const std::vector<cv::Point2f>& corners);
  /// @brief Lower-level: a plane view from corners and decoded primitives.
  void addPlaneSamples(const std::string& name, const std::vector<cv::Point2f>& corners,
                       const std::vector<PrimitiveSample>& samples);
  /// @brief Lower-level: a known-distance plane view from decoded primitives.
  void addDistanceSamples(const std::string& name, double distance, const std::vector<PrimitiveSample>& samples);

  /// @brief Decodes a pattern image with the nominal rig. @throws CalibrationError for a bad image.
  std::vector<PrimitiveSample> decode(const std::string& name, const cv::Mat& grey);

  /// @brief Board views so far (camera views and plane views with a board).
  int boardViews() const;
  /// @brief Plane views so far (with a board or a known distance).
  int planeViews() const;
  /// @brief Forgets all views (keeps a camera given by setCamera()).
  void clear();

  /**
   * @brief Runs the calibration: the camera from every board view (unless given), each plane in the
   * camera frame (board pose, or the known distance), the projector from the pattern on the planes.
   * @throws CalibrationError with a clear message for too few views or a failed fit.
   */
  FullCalibrationResult calibrate() const;

  /// @brief The board.
  const Board& board() const { return board_; }

private:
  struct PlaneView
  {
    std::string name;
    int board_view = -1;  // index into board views, or -1 for a known distance
    double distance = 0.0;
    std::vector<PrimitiveSample> samples;
  };
  void checkImage(const std::string& name, const cv::Mat& grey) const;
  // The checkerboard's corners in the image @p name. Throws if it is not found.
  std::vector<cv::Point2f> findCorners(const std::string& name, const cv::Mat& grey) const;
  // Throws if too few primitives of the pattern image @p name were decoded.
  void checkSamples(const std::string& name, const std::vector<PrimitiveSample>& samples) const;

  // The steps of calibrate(). 1: the camera (calibrated from the board views, or the one given)
  // and the board poses.
  std::vector<sl_projector::RigidTransform> calibrateCameraStep(FullCalibrationResult& out) const;
  // 2, 3: each plane view's plane in the camera frame (its board's pose, or the known distance) and
  // its projector correspondences.
  std::vector<ProjectorCorrespondence> planeCorrespondences(
      const sl_projector::Rig& rig, const std::vector<sl_projector::RigidTransform>& board_poses,
      FullCalibrationResult& out) const;
  // 4: the joint refinement on the projector fit's inliers; keeps the separate fits if it diverges.
  void refineJointly(const sl_projector::Rig& rig, const std::vector<ProjectorCorrespondence>& corr,
                     std::vector<sl_projector::RigidTransform>& board_poses, FullCalibrationResult& out) const;
  // 5: the board corners' residuals with the final camera and board poses.
  std::vector<ImageResidual> cornerResiduals(const FullCalibrationResult& out) const;

  sl_projector::Rig rig_;
  Board board_;
  FullCalibrationOptions options_;
  bool camera_given_ = false;
  sl_projector::PinholeModel camera_;
  std::vector<BoardView> board_views_;
  std::vector<std::vector<EdgeBlur>> board_blur_;  // per board view: its edges' blur (none from corners alone)
  std::vector<PlaneView> plane_views_;
  std::unique_ptr<sl_decoder::Decoder> decoder_;
  sl_decoder::DecodeResult decoded_;
};

/// @brief Differences between a calibrated rig and a reference (e.g. the simulator's true rig).
struct RigComparison
{
  double camera_fx_percent = 0.0, camera_fy_percent = 0.0;        ///< relative focal length error, %
  double camera_cx_px = 0.0, camera_cy_px = 0.0;                  ///< principal point error, px
  double projector_fx_percent = 0.0, projector_fy_percent = 0.0;  ///< %
  double projector_cx_px = 0.0, projector_cy_px = 0.0;            ///< px
  double translation_mm = 0.0;                                    ///< |t - t_ref|, mm
  double baseline_mm = 0.0;                                       ///< |t| - |t_ref|, mm
  double rotation_deg = 0.0;                                      ///< angle of R^T R_ref, degrees

  /// @brief One line per quantity.
  std::string summary() const;
};

/// @brief Compares @p calibrated with @p reference.
RigComparison compareRigs(const sl_projector::Rig& calibrated, const sl_projector::Rig& reference);

}  // namespace sl_calibration
