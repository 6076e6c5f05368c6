#include "sl_decoder/calibration/full_calibration.h"

#include <cmath>
#include <sstream>

namespace sl_decoder
{
namespace calibration
{

FullCalibration::FullCalibration(const sl_projector::Rig& rig, const Board& board, const FullCalibrationOptions& options)
  : rig_(rig), board_(board), options_(options)
{
  board_.validate();
  options_.distance_planes.validate();
  rig_.validate();
  decoder_.reset(new Decoder(rig_, calibrationDecoderConfig(options_.epipolar_tolerance)));
}

FullCalibration::~FullCalibration() = default;

void FullCalibration::setCamera(const sl_projector::PinholeModel& camera)
{
  if (camera.width != rig_.camera.width || camera.height != rig_.camera.height)
    throw CalibrationError("the given camera model is " + std::to_string(camera.width) + " x " +
                           std::to_string(camera.height) + " px, the rig's camera " + std::to_string(rig_.camera.width) +
                           " x " + std::to_string(rig_.camera.height));
  camera_ = camera;
  camera_given_ = true;
}

void FullCalibration::checkImage(const std::string& name, const cv::Mat& grey) const
{
  if (grey.empty())
    throw CalibrationError(name + ": empty image");
  if (grey.type() != CV_8UC1)
    throw CalibrationError(name + ": not an 8-bit grey image");
  if (grey.cols != rig_.camera.width || grey.rows != rig_.camera.height)
    throw CalibrationError(name + ": the image is " + std::to_string(grey.cols) + " x " + std::to_string(grey.rows) +
                           " px, the rig's camera " + std::to_string(rig_.camera.width) + " x " +
                           std::to_string(rig_.camera.height));
}

void FullCalibration::addCameraView(const std::string& name, const cv::Mat& grey)
{
  checkImage(name, grey);
  std::vector<cv::Point2f> corners;
  if (!findBoardCorners(grey, board_, corners))
    throw CalibrationError(name + ": checkerboard of " + std::to_string(board_.cols) + "x" + std::to_string(board_.rows) +
                           " inner corners not found (the whole board must be visible, lit, and in focus)");
  addCameraCorners(name, corners);
}

void FullCalibration::addCameraCorners(const std::string& name, const std::vector<cv::Point2f>& corners)
{
  if (corners.size() != static_cast<size_t>(board_.cols * board_.rows))
    throw CalibrationError(name + ": " + std::to_string(corners.size()) + " corners, the board has " +
                           std::to_string(board_.cols * board_.rows));
  board_views_.push_back(BoardView{ name, corners });
}

std::vector<PrimitiveSample> FullCalibration::decode(const std::string& name, const cv::Mat& grey)
{
  checkImage(name, grey);
  try
  {
    decoder_->decode(grey, decoded_);
  }
  catch (const std::invalid_argument& e)
  {
    throw CalibrationError(name + ": " + e.what());
  }
  return decodedSamples(decoded_);
}

void FullCalibration::addPlaneView(const std::string& board_name, const cv::Mat& board_grey,
                                   const std::string& pattern_name, const cv::Mat& pattern_grey)
{
  checkImage(board_name, board_grey);
  std::vector<cv::Point2f> corners;
  if (!findBoardCorners(board_grey, board_, corners))
    throw CalibrationError(board_name + ": checkerboard of " + std::to_string(board_.cols) + "x" +
                           std::to_string(board_.rows) +
                           " inner corners not found (the whole board must be visible, lit, and in focus)");
  const std::vector<PrimitiveSample> samples = decode(pattern_name, pattern_grey);
  addPlaneSamples(board_name + " + " + pattern_name, corners, samples);
}

void FullCalibration::addDistanceView(const std::string& pattern_name, const cv::Mat& pattern_grey, double distance)
{
  const std::vector<PrimitiveSample> samples = decode(pattern_name, pattern_grey);
  addDistanceSamples(pattern_name, distance, samples);
}

void FullCalibration::addPlaneSamples(const std::string& name, const std::vector<cv::Point2f>& corners,
                                      const std::vector<PrimitiveSample>& samples)
{
  if (static_cast<int>(samples.size()) < options_.projector.min_points_per_view)
    throw CalibrationError(name + ": only " + std::to_string(samples.size()) +
                           " pattern primitives decoded (need " + std::to_string(options_.projector.min_points_per_view) +
                           "): is the projector on and the pattern on the plane?");
  addCameraCorners(name, corners);
  PlaneView v;
  v.name = name;
  v.board_view = static_cast<int>(board_views_.size()) - 1;
  v.samples = samples;
  plane_views_.push_back(std::move(v));
}

void FullCalibration::addDistanceSamples(const std::string& name, double distance,
                                         const std::vector<PrimitiveSample>& samples)
{
  if (!std::isfinite(distance) || distance <= 0.0 || distance > 20.0)
    throw CalibrationError(name + ": the plane distance must be a positive number of metres, got " +
                           std::to_string(distance));
  if (static_cast<int>(samples.size()) < options_.projector.min_points_per_view)
    throw CalibrationError(name + ": only " + std::to_string(samples.size()) +
                           " pattern primitives decoded (need " + std::to_string(options_.projector.min_points_per_view) +
                           "): is the projector on and the pattern on the plane?");
  PlaneView v;
  v.name = name;
  v.distance = distance;
  v.samples = samples;
  plane_views_.push_back(std::move(v));
}

int FullCalibration::boardViews() const
{
  return static_cast<int>(board_views_.size());
}

int FullCalibration::planeViews() const
{
  return static_cast<int>(plane_views_.size());
}

void FullCalibration::clear()
{
  board_views_.clear();
  plane_views_.clear();
}

FullCalibrationResult FullCalibration::calibrate() const
{
  FullCalibrationResult out;
  if (static_cast<int>(plane_views_.size()) < options_.projector.min_views)
    throw CalibrationError("full calibration needs >= " + std::to_string(options_.projector.min_views) +
                           " plane poses with the pattern (board + pattern image, or pattern image at a known "
                           "distance), got " + std::to_string(plane_views_.size()));
  // 1. Camera.
  std::vector<sl_projector::RigidTransform> board_poses(board_views_.size());
  if (camera_given_)
  {
    out.camera.camera = camera_;
    for (size_t i = 0; i < board_views_.size(); ++i)
    {
      double rms = 0.0;
      board_poses[i] = boardPose(camera_, board_, board_views_[i].corners, &rms);
      out.camera.view_rms.push_back(rms);
      out.camera_views.push_back(board_views_[i].name);
    }
    out.camera.board_poses = board_poses;
  }
  else
  {
    if (static_cast<int>(board_views_.size()) < options_.camera.min_views)
      throw CalibrationError("camera calibration needs >= " + std::to_string(options_.camera.min_views) +
                             " checkerboard views at different orientations, got " +
                             std::to_string(board_views_.size()) +
                             " (or give the camera model, e.g. from ROS camera_calibration)");
    out.camera = calibrateCamera(board_views_, board_, cv::Size(rig_.camera.width, rig_.camera.height), options_.camera);
    out.camera_calibrated = true;
    board_poses = out.camera.board_poses;
    for (const BoardView& v : board_views_)
      out.camera_views.push_back(v.name);
  }
  const sl_projector::PinholeModel& camera = out.camera.camera;

  // 2. Planes in the camera frame, 3. projector correspondences.
  sl_projector::Rig rig = rig_;
  rig.camera = camera;
  const sl_projector::Pattern pattern(rig.pattern);
  std::vector<ProjectorCorrespondence> corr;
  for (size_t i = 0; i < plane_views_.size(); ++i)
  {
    const PlaneView& v = plane_views_[i];
    CalibrationPlane plane;
    if (v.board_view >= 0)
      plane = planeOfBoard(board_poses[static_cast<size_t>(v.board_view)]);
    else
    {
      try
      {
        plane = planeAtDistance(rig, v.distance, options_.distance_planes);
      }
      catch (const std::invalid_argument& e)
      {
        throw CalibrationError(v.name + ": " + e.what());
      }
    }
    const std::vector<ProjectorCorrespondence> c =
        projectorCorrespondences(pattern, camera, plane, v.samples, static_cast<int>(i));
    corr.insert(corr.end(), c.begin(), c.end());
    out.plane_views.push_back(v.name);
  }
  out.projector = calibrateProjector(corr, rig.projector.width, rig.projector.height, options_.projector);

  rig.projector = out.projector.projector;
  rig.projector_pose = out.projector.pose;
  try
  {
    rig.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw CalibrationError(std::string("the calibrated rig is not valid: ") + e.what());
  }
  out.rig = rig;
  return out;
}

namespace
{
std::string model(const sl_projector::PinholeModel& m)
{
  std::ostringstream o;
  o << "fx " << fixed(m.fx, 2) << ", fy " << fixed(m.fy, 2) << ", cx " << fixed(m.cx, 2) << ", cy " << fixed(m.cy, 2)
    << " px; D [" << fixed(m.dist[0], 5) << ", " << fixed(m.dist[1], 5) << ", " << fixed(m.dist[2], 5) << ", "
    << fixed(m.dist[3], 5) << ", " << fixed(m.dist[4], 5) << "]";
  return o.str();
}
}  // namespace

std::string FullCalibrationResult::summary() const
{
  std::ostringstream o;
  o << "camera (" << (camera_calibrated ? "calibrated" : "given") << "): " << model(camera.camera) << "\n";
  if (camera_calibrated)
    o << "  reprojection error " << fixed(camera.rms, 3) << " px rms over " << camera_views.size() << " board views\n";
  for (size_t i = 0; i < camera_views.size() && i < camera.view_rms.size(); ++i)
    o << "    " << fixed(camera.view_rms[i], 3) << " px  " << camera_views[i] << "\n";
  o << "projector: " << model(projector.projector) << "\n";
  o << "  reprojection error " << fixed(projector.rms, 3) << " px rms over " << projector.points << " primitives on "
    << plane_views.size() << " plane views (" << projector.outliers << " outliers dropped)\n";
  for (size_t i = 0; i < plane_views.size() && i < projector.view_rms.size(); ++i)
    o << "    " << fixed(projector.view_rms[i], 3) << " px  " << projector.view_points[i] << " primitives  "
      << plane_views[i] << "\n";
  const Eigen::Matrix3d& R = projector.pose.rotation;
  const Eigen::Vector3d& t = projector.pose.translation;
  const Eigen::AngleAxisd aa(R);
  o << "projector pose in the camera frame: translation [" << fixed(1000 * t.x(), 2) << ", " << fixed(1000 * t.y(), 2)
    << ", " << fixed(1000 * t.z(), 2) << "] mm (baseline " << fixed(1000 * t.norm(), 2) << " mm), rotation "
    << fixed(aa.angle() * 180.0 / M_PI, 3) << " deg about [" << fixed(aa.axis().x(), 3) << ", "
    << fixed(aa.axis().y(), 3) << ", " << fixed(aa.axis().z(), 3) << "]\n";
  return o.str();
}

RigComparison compareRigs(const sl_projector::Rig& a, const sl_projector::Rig& ref)
{
  RigComparison c;
  c.camera_fx_percent = 100.0 * (a.camera.fx - ref.camera.fx) / ref.camera.fx;
  c.camera_fy_percent = 100.0 * (a.camera.fy - ref.camera.fy) / ref.camera.fy;
  c.camera_cx_px = a.camera.cx - ref.camera.cx;
  c.camera_cy_px = a.camera.cy - ref.camera.cy;
  c.projector_fx_percent = 100.0 * (a.projector.fx - ref.projector.fx) / ref.projector.fx;
  c.projector_fy_percent = 100.0 * (a.projector.fy - ref.projector.fy) / ref.projector.fy;
  c.projector_cx_px = a.projector.cx - ref.projector.cx;
  c.projector_cy_px = a.projector.cy - ref.projector.cy;
  c.translation_mm = 1000.0 * (a.projector_pose.translation - ref.projector_pose.translation).norm();
  c.baseline_mm = 1000.0 * (a.projector_pose.translation.norm() - ref.projector_pose.translation.norm());
  c.rotation_deg = rotationAngle(a.projector_pose.rotation, ref.projector_pose.rotation) * 180.0 / M_PI;
  return c;
}

std::string RigComparison::summary() const
{
  std::ostringstream o;
  o << "camera focal length error: fx " << fixed(camera_fx_percent, 3) << " %, fy " << fixed(camera_fy_percent, 3)
    << " %\n";
  o << "camera principal point error: cx " << fixed(camera_cx_px, 2) << " px, cy " << fixed(camera_cy_px, 2) << " px\n";
  o << "projector focal length error: fx " << fixed(projector_fx_percent, 3) << " %, fy "
    << fixed(projector_fy_percent, 3) << " %\n";
  o << "projector principal point error: cx " << fixed(projector_cx_px, 2) << " px, cy " << fixed(projector_cy_px, 2)
    << " px\n";
  o << "projector translation error: " << fixed(translation_mm, 3) << " mm (baseline length " << fixed(baseline_mm, 3)
    << " mm)\n";
  o << "projector rotation error: " << fixed(rotation_deg, 4) << " deg\n";
  return o.str();
}

}  // namespace calibration
}  // namespace sl_decoder
