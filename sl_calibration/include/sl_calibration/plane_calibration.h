#pragma once
/// @file plane_calibration.h
/// @brief Plane calibration (the prototype's method, done right): per-primitive depth models fitted
/// to the image column of each pattern primitive seen on a flat plane at N >= 3 known distances
/// (ROS-free).

#include <string>
#include <vector>

#include "sl_calibration/common.h"
#include "sl_rig/rig.h"

namespace sl_calibration
{

/**
 * @brief What a calibration distance is measured from.
 *
 * The plane is perpendicular to the robot's x axis (the x axis of the mount's parent frame,
 * `platform_edge`), or to the camera's optical axis with PlaneNormal::Camera.
 */
enum class DistanceReference
{
  Camera,  ///< from the camera's optical centre (mount.xyz), along the normal: the prototype's and the simulator
           ///< scenes' convention
  Edge     ///< from the origin of the mount's parent frame (the robot's front edge), along the robot's x axis
};

/// @brief Orientation of the calibration plane.
enum class PlaneNormal
{
  Robot,  ///< perpendicular to the robot's x axis (the mount tells its normal in the camera frame)
  Camera  ///< perpendicular to the camera's optical axis
};

/// @brief Parses "camera" or "edge". @throws std::invalid_argument otherwise.
DistanceReference parseDistanceReference(const std::string& name);
/// @brief Parses "robot" or "camera". @throws std::invalid_argument otherwise.
PlaneNormal parsePlaneNormal(const std::string& name);

/// @brief Settings of the plane calibration.
struct PlaneCalibrationOptions
{
  /// Distinct distances a primitive must be seen at to be calibrated (>= 3: the rational model has 3 parameters).
  int min_distances = 3;
  /// Distances closer than this are the same plane, m.
  double same_distance = 0.001;
  /// A primitive whose rational fit leaves a larger rms is rejected (an inconsistent decode), m.
  double max_rational_rms = 0.003;
  /// What the distances are measured from.
  DistanceReference reference = DistanceReference::Camera;
  /// Orientation of the plane.
  PlaneNormal normal = PlaneNormal::Robot;

  /// @brief Checks every field. @throws std::invalid_argument naming the field.
  void validate() const;
};

/**
 * @brief The calibration plane at @p distance (m) in the camera optical frame of @p rig.
 *
 * Robot normal: the plane x = d in the mount's parent frame (x forward), with d = mount.xyz.x +
 * distance (reference Camera) or d = distance (reference Edge), carried into the camera frame with
 * the mount. Camera normal: the plane z = distance in the camera frame (the reference must be
 * Camera).
 * @throws std::invalid_argument for a distance that puts the plane behind the camera.
 */
CalibrationPlane planeAtDistance(const sl_projector::Rig& rig, double distance, const PlaneCalibrationOptions& options);

/**
 * @brief The depth (camera z, m) of the point where the camera ray through pixel (u, v) meets
 * @p plane; NaN if it does not meet it in front of the camera. This is the target depth of a
 * primitive seen at (u, v) on a calibration plane.
 */
double depthOnPlane(const sl_projector::PinholeModel& camera, const CalibrationPlane& plane, double u, double v);

/**
 * @brief Least-squares fit of depth = a + b u (the prototype's model). Exact for two points.
 * @return an invalid model if there are fewer than 2 points or all u are equal.
 */
sl_projector::DepthModel fitLinear(const std::vector<double>& u, const std::vector<double>& depth);

/**
 * @brief Fit of depth = (a + b u) / (1 + c u) (the exact per-primitive model): exact for three
 * points, least squares on the depth residual (Gauss-Newton from the algebraic solution) for more.
 * @return an invalid model if there are fewer than 3 points, the points are degenerate, or the
 * fitted curve has a pole inside the observed range of u.
 */
sl_projector::DepthModel fitRational(const std::vector<double>& u, const std::vector<double>& depth);

/// @brief The fit and its residuals for one primitive.
struct PrimitiveFit
{
  int row = 0;                        ///< pattern row
  int col = 0;                        ///< pattern column
  int distances = 0;                  ///< distinct distances it was seen at
  sl_projector::DepthModel linear;    ///< prototype's model (valid when calibrated)
  sl_projector::DepthModel rational;  ///< rational model (valid when calibrated)
  bool rejected = false;              ///< seen often enough, but the rational fit was inconsistent
  /// Per calibration distance (index into PlaneCalibrationResult::distances): median image column
  /// (NaN where not seen), target depth, and the residuals model - target, m.
  std::vector<double> u, depth, linear_residual, rational_residual;
  std::vector<double> v;  ///< per calibration distance: median image row, px (NaN where not seen)
};

/// @brief Residual statistics of one calibration distance.
struct DistanceSummary
{
  double distance = 0.0;      ///< m, as given
  int images = 0;             ///< images at this distance
  int primitives = 0;         ///< distinct primitives decoded at this distance
  int calibrated = 0;         ///< of which calibrated
  double linear_rms = 0.0;    ///< rms residual of the linear model over the calibrated primitives, m
  double rational_rms = 0.0;  ///< rms residual of the rational model, m
  double linear_max = 0.0;    ///< largest |residual|, m
  double rational_max = 0.0;  ///< largest |residual|, m
};

/// @brief Everything the plane calibration produced.
struct PlaneCalibrationResult
{
  std::vector<DistanceSummary> distances;  ///< distinct distances, ascending
  std::vector<PrimitiveFit> primitives;    ///< every primitive seen at least once, row-major order
  sl_projector::DepthTables tables;        ///< rows x cols tables for the rig file
  int seen = 0;                            ///< primitives seen at all
  int calibrated = 0;                      ///< primitives with both models
  int too_few = 0;                         ///< seen, but at fewer than min_distances distances
  int rejected = 0;                        ///< seen often enough but inconsistent (rms above max_rational_rms)
  double linear_rms = 0.0;                 ///< rms residual over every calibrated primitive and distance, m
  double rational_rms = 0.0;               ///< m

  /// @brief A human-readable summary: per distance and overall, and the primitives left out.
  std::string summary() const;
  /**
   * @brief Per-primitive residuals as CSV: row, col, distances, then per distance u (px), linear and
   * rational residual (mm), and a status (calibrated, too_few_distances, rejected).
   */
  std::string residualsCsv() const;
  /**
   * @brief The rational model's residuals in the image: for every calibrated primitive at every
   * distance its model was fitted on, at its median pixel there, the column where the model puts the
   * plane's depth minus the column where it was seen (the row residual is 0). `view` is the index
   * into distances.
   */
  std::vector<ImageResidual> columnResiduals() const;
};

/**
 * @brief Collects decoded primitives of a plane at known distances and fits both models.
 *
 * Images at the same distance are pooled: each primitive's image position at a distance is the
 * median over the images there. The target depth of a primitive is depthOnPlane() at that position.
 */
class PlaneCalibration
{
public:
  /**
   * @param rig the rig: its camera model and mount define the planes, its pattern the table size.
   * @throws std::invalid_argument for invalid options.
   */
  explicit PlaneCalibration(const sl_projector::Rig& rig,
                            const PlaneCalibrationOptions& options = PlaneCalibrationOptions());

  /**
   * @brief Adds the decoded primitives of one image of the plane at @p distance (m).
   * @param source names the image in messages.
   * @return the number of primitives added.
   * @throws CalibrationError for a distance that is not finite and positive, or a plane behind the camera.
   */
  int addSamples(double distance, const std::vector<PrimitiveSample>& samples, const std::string& source = "");

  /// @brief Same as addSamples(distance, decodedSamples(result), source).
  int addImage(double distance, const sl_decoder::DecodeResult& result, const std::string& source = "");

  /// @brief Distinct distances so far, ascending, m.
  std::vector<double> distances() const;

  /// @brief Images added so far.
  int images() const { return images_; }

  /// @brief Forgets everything added.
  void clear();

  /**
   * @brief Fits both models for every primitive seen at enough distances.
   *
   * In steps: the distances; per primitive its median image position and target depth at each, the
   * rational model (leaving out one inconsistent distance if that fixes it; still inconsistent:
   * rejected), the linear model on the same distances; the residual statistics per distance.
   * @throws CalibrationError with a clear message when there are fewer than min_distances distinct
   * distances, or no primitive was seen at enough of them.
   */
  PlaneCalibrationResult fit() const;

  /// @brief The options.
  const PlaneCalibrationOptions& options() const { return options_; }

private:
  struct Group
  {
    double distance;
    CalibrationPlane plane;
    int images = 0;
    std::vector<std::vector<Eigen::Vector2d>> pixels;  // per primitive
  };
  int groupFor(double distance);
  // The steps of fit(). Step 1: the groups in ascending order of distance, their summaries in @p res,
  // the tables sized; throws for too few distances.
  std::vector<size_t> startResult(PlaneCalibrationResult& res) const;
  // Step 2: the primitive @p cell (row-major) at each distance of @p order: median image position and
  // target depth; @p seen_at gets the distances where it has both.
  PrimitiveFit observe(size_t cell, const std::vector<size_t>& order, std::vector<size_t>& seen_at) const;

  sl_projector::Rig rig_;
  PlaneCalibrationOptions options_;
  std::vector<Group> groups_;
  int images_ = 0;
};

/// @brief @p rig with the tables of @p result (distances, linear and rational).
sl_projector::Rig withTables(const sl_projector::Rig& rig, const PlaneCalibrationResult& result);

}  // namespace sl_calibration
