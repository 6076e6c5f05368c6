#pragma once
/// @file common.h
/// @brief Types shared by the plane and the full (projector-camera) calibration (ROS-free).

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "sl_decoder/decoder.h"
#include "sl_rig/rig.h"

namespace sl_calibration
{

/**
 * @brief Thrown for input that cannot be calibrated (too few views or distances, a checkerboard
 * not found, an unreadable file ...). what() says what is wrong and names the image or file.
 */
class CalibrationError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/**
 * @brief A plane in the camera optical frame: the points p with normal.dot(p) == offset.
 *
 * The normal is a unit vector pointing away from the camera (offset > 0 for a plane in front).
 */
struct CalibrationPlane
{
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit normal, camera frame
  double offset = 1.0;                                ///< distance of the plane from the camera centre, m

  /**
   * @brief Point where the camera ray through @p ray (any direction with z > 0, camera frame) meets
   * the plane.
   * @return false if the ray is (nearly) parallel to the plane or meets it behind the camera.
   */
  bool intersect(const Eigen::Vector3d& ray, Eigen::Vector3d& point) const;
};

/**
 * @brief One decoded primitive of one image: pattern (row, col) and its sub-pixel image position.
 */
struct PrimitiveSample
{
  int row = -1;    ///< pattern row
  int col = -1;    ///< pattern column
  double u = 0.0;  ///< image column, px (pixel centres at integers)
  double v = 0.0;  ///< image row, px
};

/**
 * @brief One reprojection residual in an image: where a point was observed and how far its model
 * puts it from there.
 */
struct ImageResidual
{
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();     ///< observed position, px (pixel centres at integers)
  Eigen::Vector2d residual = Eigen::Vector2d::Zero();  ///< predicted minus observed position, px
  int view = 0;                                        ///< the view it belongs to (board view, distance), from 0
};

/**
 * @brief The decoded primitives of a decode result: every blob with a (row, col) and a 3D point
 * (so it passed the decoder's depth range and confidence checks).
 */
std::vector<PrimitiveSample> decodedSamples(const sl_decoder::DecodeResult& result);

/**
 * @brief Default epipolar tolerance of the decoder on calibration images, px: a loose prior. A rig
 * measured with a ruler (baseline off by 10 mm, focal lengths by 3 %, each angle by 1 degree) puts
 * primitives tens of pixels off their epipolar curves, and there a whole lattice shifted by a row
 * fits the geometry as well as the true one. Calibration images are therefore identified by the
 * code (sl_decoder::DecoderConfig::identify_by_words); the geometry only rules out the absurd.
 */
constexpr double kCalibrationEpipolarTolerance = 40.0;

/**
 * @brief Decoder settings for calibration images: the decoder's defaults with triangulation (the
 * rig being calibrated may have no depth tables yet), identification by the words, and the given
 * epipolar tolerance (px).
 */
sl_decoder::DecoderConfig calibrationDecoderConfig(double epipolar_tolerance = kCalibrationEpipolarTolerance);

/**
 * @brief Reads an image file as 8-bit grey (colour is converted, 16-bit scaled to 8).
 * @throws CalibrationError naming @p path if it cannot be read.
 */
cv::Mat readGreyImage(const std::string& path);

/**
 * @brief The image files of a folder (png, jpg, jpeg, pgm, ppm, pnm, bmp, tif, tiff; any case) in
 * byte-wise order of their names, or @p path itself if it is a file.
 * @throws CalibrationError if the path does not exist or a folder has no images.
 */
std::vector<std::string> listImages(const std::string& path);

/**
 * @brief Splits "PATH:NUMBER" at the last ':' (e.g. "plane_500.png:0.5").
 * @throws CalibrationError naming @p spec if there is no ':' or the number does not parse.
 */
void parsePathAndNumber(const std::string& spec, std::string& path, double& number);

/// @brief Parses a comma-separated list of numbers ("0.5,0.6,0.7"). @throws std::invalid_argument.
std::vector<double> parseNumberList(const std::string& text);

/// @brief Angle of the rotation @p a^T * @p b, rad.
double rotationAngle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

/// @brief Formats @p value with @p digits decimals.
std::string fixed(double value, int digits);

}  // namespace sl_calibration
