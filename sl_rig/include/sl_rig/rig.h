#pragma once
/// @file rig.h
/// @brief The projector-camera rig: pinhole models with distortion, the projector's pose in the
/// camera optical frame, the pattern and the mount on the robot (ROS-free).

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "sl_rig/limits.h"
#include "sl_rig/pattern.h"

namespace sl_projector
{

/**
 * @brief A pinhole camera (or projector, as an inverse camera) with OpenCV's radial-tangential
 * distortion (plumb_bob: k1, k2, p1, p2, k3).
 *
 * Pixel coordinates: x right, y down, the centre of the top-left pixel at (0, 0). The optical frame
 * is x right, y down, z forward (REP 103 optical convention).
 */
struct PinholeModel
{
  int width = 0;                                              ///< image width, px
  int height = 0;                                             ///< image height, px
  double fx = 0.0;                                            ///< focal length, px
  double fy = 0.0;                                            ///< focal length, px
  double cx = 0.0;                                            ///< principal point, px
  double cy = 0.0;                                            ///< principal point, px
  std::array<double, 5> dist{ { 0.0, 0.0, 0.0, 0.0, 0.0 } };  ///< k1, k2, p1, p2, k3

  /// @brief Applies the distortion to normalised coordinates (x/z, y/z).
  Eigen::Vector2d distort(const Eigen::Vector2d& normalized) const;

  /**
   * @brief Inverts distort() by fixed-point iteration (converges for the moderate distortion of real
   * lenses; accurate to < 1e-9 normalised units within the image).
   */
  Eigen::Vector2d undistort(const Eigen::Vector2d& distorted) const;

  /// @brief Pixel of a point in the optical frame (z > 0 expected; returns NaN for z <= 0).
  Eigen::Vector2d project(const Eigen::Vector3d& point) const;

  /// @brief Ray direction (x, y, 1) in the optical frame through pixel @p pixel (distortion removed).
  Eigen::Vector3d ray(const Eigen::Vector2d& pixel) const;

  /// @brief True if @p pixel lies inside the image (pixel centres 0..width-1, 0..height-1, with
  /// half a pixel of border).
  bool inImage(const Eigen::Vector2d& pixel) const
  {
    return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() < width - 0.5 && pixel.y() < height - 0.5;
  }

  /// @brief The camera matrix as cv::Matx33d.
  cv::Matx33d cameraMatrix() const { return { fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0 }; }

  /// @brief True if there is any distortion.
  bool distorted() const;
};

/**
 * @brief The optics of a lens as the thin-lens model sees them: where it is focused, its aperture
 * and the pitch that turns its focal length from pixels into metres.
 *
 * A point at depth z (along the optical axis) is blurred into a disc of diameter
 * `(f / N) * f_px * z_f / (z_f - f) * |1/z - 1/z_f|` px, with f = f_px * pixel_pitch the focal
 * length in metres (defocusDiameter()). The simulator renders with these and the
 * decoder expects the blur they give.
 */
struct LensOptics
{
  double focus_distance = 0.675;  ///< depth the lens is focused at, m
  double f_number = 1.4;          ///< focal length / aperture diameter
  double pixel_pitch = 6.0e-6;    ///< size of one pixel (sensor or projector mirror), m

  /// @brief Thin-lens blur circle diameter, px, of a point at depth @p depth m for a lens of
  /// focal length @p f_px px. 0 at the focus distance.
  double defocusDiameter(double f_px, double depth) const;
  /// @brief The factor k of defocusDiameter() = k |1/depth - 1/focus_distance| (px m), for a lens
  /// of focal length @p f_px px: `(f / N) * f_px * z_f / (z_f - f)`.
  double defocusPerInverseDepth(double f_px) const;
};

/// @brief A rigid transform: p_parent = rotation * p_child + translation (metres).
struct RigidTransform
{
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< child axes in the parent frame
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();   ///< child origin in the parent frame, m

  /// @brief Applies the transform to a point.
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return rotation * p + translation; }
  /// @brief The inverse transform.
  RigidTransform inverse() const;
};

/**
 * @brief Per-primitive depth model from plane calibration: depth as a function of the primitive's
 * image column u (px).
 *
 * linear: depth = a + b * u (the prototype's model); rational: depth = (a + b * u) / (1 + c * u),
 * the exact form for a plane-induced 1D homography. Depth is the z of the camera optical frame, m.
 */
struct DepthModel
{
  bool valid = false;  ///< false where the primitive was not seen often enough to fit
  double a = 0.0;      ///< m
  double b = 0.0;      ///< m / px
  double c = 0.0;      ///< 1 / px (0 for the linear model)
  double rms = 0.0;    ///< fit residual, m
  /// @brief Depth at column @p u.
  double depth(double u) const { return (a + b * u) / (1.0 + c * u); }
};

/// @brief Per-primitive depth tables (rows x cols of the pattern; empty when not calibrated).
struct DepthTables
{
  std::vector<DepthModel> linear;    ///< row-major, rows * cols entries, or empty
  std::vector<DepthModel> rational;  ///< row-major, rows * cols entries, or empty
  std::vector<double> distances;     ///< the calibration plane distances, m (information only)
};

/// @brief Where the rig sits on the robot: the pose of `camera_link` (x forward, y left, z up) in
/// the robot's `platform_edge` frame. The camera optical frame is camera_link rotated by
/// roll = -pi/2, yaw = -pi/2 (REP 103).
struct Mount
{
  std::string parent_frame = "platform_edge";     ///< frame the mount is given in
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();  ///< camera_link origin, m
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();  ///< camera_link roll, pitch, yaw, rad
  /// @brief The camera optical frame in the parent frame.
  RigidTransform cameraOpticalInParent() const;
};

/**
 * @brief The whole rig, as stored in the calibration file.
 */
struct Rig
{
  PinholeModel camera;            ///< the camera
  PinholeModel projector;         ///< the projector as an inverse camera, frame-buffer pixels
  RigidTransform projector_pose;  ///< projector optical frame in the camera optical frame
  PatternConfig pattern;          ///< the projected pattern
  Mount mount;                    ///< camera on the robot
  DepthTables tables;             ///< optional plane-calibration tables
  /// Camera lens optics (rig file: `camera.focus_distance`, `camera.f_number`, `camera.pixel_pitch`).
  LensOptics camera_optics;
  /// Projector lens optics (rig file: `projector.*`); a DLP pico projector's defaults.
  LensOptics projector_optics{ 0.675, 1.8, 7.6e-6 };

  /// @brief Projector centre in the camera optical frame, m.
  Eigen::Vector3d projectorCentre() const { return projector_pose.translation; }

  /**
   * @brief Ray of the projector through projector pixel @p projector_pixel, in the camera frame:
   * origin (projector centre) and unit direction.
   */
  void projectorRay(const Eigen::Vector2d& projector_pixel, Eigen::Vector3d& origin, Eigen::Vector3d& direction) const;

  /**
   * @brief Triangulates a camera pixel with the projector pixel it sees: the point of the camera ray
   * closest to the projector ray (the camera pixel is the measured one; the projector pixel is exact).
   * @param[out] point camera optical frame, m.
   * @param[out] ray_distance distance between the two rays at the solution, m (an epipolar check).
   * @return false if the rays are (nearly) parallel or the point is behind the camera.
   */
  bool triangulate(const Eigen::Vector2d& camera_pixel, const Eigen::Vector2d& projector_pixel, Eigen::Vector3d& point,
                   double* ray_distance = nullptr) const;

  /**
   * @brief Checks the rig for consistency.
   *
   * Camera and projector images must be at most kMaxImageSide px a side and kMaxImagePixels px in
   * all (limits.h); the pattern as PatternConfig::validate(); each lens's optics finite, the
   * focus distance beyond the focal length.
   * @throws std::invalid_argument naming the offending key (e.g. "projector_pose.rotation").
   */
  void validate() const;
};

/**
 * @brief Thrown when a rig file cannot be read; what() names the file and the key.
 */
class RigFileError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/**
 * @brief Loads a rig (calibration) file. See sl_rig/README.md ("Rig file") for the format.
 * @throws RigFileError if the file is missing, malformed or inconsistent (also a key of the wrong
 * YAML type, e.g. `mount: 1`, and a key the format does not have, checked by sl_rig::checkKeys());
 * the message names the file and the key. No yaml-cpp exception escapes.
 */
Rig loadRig(const std::string& path);

/// @brief Parses a rig from YAML text; @p source names it in error messages.
/// @throws RigFileError as loadRig().
Rig parseRig(const std::string& yaml_text, const std::string& source = "<string>");

/// @brief Serialises a rig to YAML text (round-trips through parseRig(): every number reads back
/// exactly).
std::string rigToYaml(const Rig& rig);

/// @brief Writes a rig file. @throws RigFileError if it cannot be written.
void saveRig(const Rig& rig, const std::string& path);

/// @brief Rotation matrix from roll, pitch, yaw (fixed axes x, y, z; R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Matrix3d rotationFromRpy(const Eigen::Vector3d& rpy);

}  // namespace sl_projector
