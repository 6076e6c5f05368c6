#include "sl_calibration/full_calibration.h"

#include <cmath>
#include <map>
#include <sstream>

#include "sl_calibration/optimizer.h"

namespace sl_calibration
{

FullCalibration::FullCalibration(const sl_projector::Rig& rig, const Board& board,
                                 const FullCalibrationOptions& options)
  : rig_(rig), board_(board), options_(options)
{
  board_.validate();
  options_.distance_planes.validate();
  rig_.validate();
  decoder_.reset(new sl_decoder::Decoder(rig_, calibrationDecoderConfig(options_.epipolar_tolerance)));
}

FullCalibration::~FullCalibration() = default;

void FullCalibration::setCamera(const sl_projector::PinholeModel& camera)
{
  if (camera.width != rig_.camera.width || camera.height != rig_.camera.height)
    throw CalibrationError("the given camera model is " + std::to_string(camera.width) + " x " +
                           std::to_string(camera.height) + " px, the rig's camera " +
                           std::to_string(rig_.camera.width) + " x " + std::to_string(rig_.camera.height));
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

std::vector<cv::Point2f> FullCalibration::findCorners(const std::string& name, const cv::Mat& grey) const
{
  checkImage(name, grey);
  std::vector<cv::Point2f> corners;
  if (!findBoardCorners(grey, board_, corners))
    throw CalibrationError(name + ": checkerboard of " + std::to_string(board_.cols) + "x" +
                           std::to_string(board_.rows) +
                           " inner corners not found (the whole board must be visible, lit, and in focus)");
  return corners;
}

void FullCalibration::checkSamples(const std::string& name, const std::vector<PrimitiveSample>& samples) const
{
  if (static_cast<int>(samples.size()) < options_.projector.min_points_per_view)
    throw CalibrationError(name + ": only " + std::to_string(samples.size()) + " pattern primitives decoded (need " +
                           std::to_string(options_.projector.min_points_per_view) +
                           "): is the projector on and the pattern on the plane?");
}

void FullCalibration::addCameraView(const std::string& name, const cv::Mat& grey)
{
  const std::vector<cv::Point2f> corners = findCorners(name, grey);
  addCameraCorners(name, corners);
  board_blur_.back() = measureBoardEdgeBlur(grey, board_, corners);
}

void FullCalibration::addCameraCorners(const std::string& name, const std::vector<cv::Point2f>& corners)
{
  if (corners.size() != static_cast<size_t>(board_.cols * board_.rows))
    throw CalibrationError(name + ": " + std::to_string(corners.size()) + " corners, the board has " +
                           std::to_string(board_.cols * board_.rows));
  board_views_.push_back(BoardView{ name, corners });
  board_blur_.emplace_back();
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
  const std::vector<cv::Point2f> corners = findCorners(board_name, board_grey);
  const std::vector<PrimitiveSample> samples = decode(pattern_name, pattern_grey);
  checkSamples(pattern_name, samples);
  addPlaneSamples(board_name + " + " + pattern_name, corners, samples);
  board_blur_.back() = measureBoardEdgeBlur(board_grey, board_, corners);
}

void FullCalibration::addDistanceView(const std::string& pattern_name, const cv::Mat& pattern_grey, double distance)
{
  const std::vector<PrimitiveSample> samples = decode(pattern_name, pattern_grey);
  addDistanceSamples(pattern_name, distance, samples);
}

void FullCalibration::addPlaneSamples(const std::string& name, const std::vector<cv::Point2f>& corners,
                                      const std::vector<PrimitiveSample>& samples)
{
  checkSamples(name, samples);
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
  checkSamples(name, samples);
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
  board_blur_.clear();
  plane_views_.clear();
}

namespace
{
Eigen::Matrix3d rotationOf(const Eigen::Vector3d& w)
{
  const double a = w.norm();
  return a < 1e-15 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

Eigen::Vector3d vectorOf(const Eigen::Matrix3d& R)
{
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

void setModel(const Eigen::VectorXd& p, int at, sl_projector::PinholeModel& m)
{
  m.fx = p(at);
  m.fy = p(at + 1);
  m.cx = p(at + 2);
  m.cy = p(at + 3);
  for (int i = 0; i < 5; ++i)
    m.dist[static_cast<size_t>(i)] = p(at + 4 + i);
}

void getModel(const sl_projector::PinholeModel& m, int at, Eigen::VectorXd& p)
{
  p.segment<4>(at) << m.fx, m.fy, m.cx, m.cy;
  for (int i = 0; i < 5; ++i)
    p(at + 4 + i) = m.dist[static_cast<size_t>(i)];
}

/// One primitive of the joint refinement: seen at `pixel` on the plane of board view `board`
/// (or on the fixed plane `plane` when board < 0), lit by projector pixel `projector`.
struct JointPrimitive
{
  int board;
  CalibrationPlane plane;
  Eigen::Vector2d pixel, projector;
  int view;
};

// Parameter layout: camera 0..8, projector 9..17, projector-from-camera rotation 18..20 and
// translation 21..23 (x_proj = R x_cam + t), then per board view the board in the camera (w, t).
constexpr int kCam = 0, kProj = 9, kPose = 18, kBoards = 24;

void jointResiduals(const Eigen::VectorXd& p, const std::vector<BoardView>& boards,
                    const std::vector<cv::Point3f>& object, const std::vector<JointPrimitive>& prims,
                    sl_projector::PinholeModel cam, sl_projector::PinholeModel proj, Eigen::VectorXd& r)
{
  setModel(p, kCam, cam);
  setModel(p, kProj, proj);
  const Eigen::Matrix3d Rp = rotationOf(p.segment<3>(kPose));
  const Eigen::Vector3d tp = p.segment<3>(kPose + 3);
  std::vector<Eigen::Matrix3d> Rb(boards.size());
  std::vector<Eigen::Vector3d> tb(boards.size());
  for (size_t j = 0; j < boards.size(); ++j)
  {
    Rb[j] = rotationOf(p.segment<3>(kBoards + 6 * static_cast<long>(j)));
    tb[j] = p.segment<3>(kBoards + 6 * static_cast<long>(j) + 3);
  }
  r.resize(static_cast<long>(2 * (boards.size() * object.size() + prims.size())));
  long k = 0;
  for (size_t j = 0; j < boards.size(); ++j)
    for (size_t i = 0; i < object.size(); ++i)
    {
      const Eigen::Vector3d P(object[i].x, object[i].y, object[i].z);
      const Eigen::Vector2d e =
          cam.project(Rb[j] * P + tb[j]) - Eigen::Vector2d(boards[j].corners[i].x, boards[j].corners[i].y);
      r(k++) = std::isfinite(e.x()) ? e.x() : 1e3;
      r(k++) = std::isfinite(e.y()) ? e.y() : 1e3;
    }
  for (const JointPrimitive& q : prims)
  {
    CalibrationPlane plane = q.plane;
    if (q.board >= 0)
    {
      plane.normal = Rb[static_cast<size_t>(q.board)].col(2);
      plane.offset = plane.normal.dot(tb[static_cast<size_t>(q.board)]);
    }
    Eigen::Vector3d X;
    Eigen::Vector2d e(1e3, 1e3);
    if (plane.intersect(cam.ray(q.pixel), X))
    {
      const Eigen::Vector3d x = Rp * X + tp;
      if (x.z() > 1e-6)
        e = proj.project(x) - q.projector;
    }
    r(k++) = e.x();
    r(k++) = e.y();
  }
}

/// The starting point of the joint refinement: the separate fits.
Eigen::VectorXd initialParameters(const sl_projector::PinholeModel& camera, const ProjectorCalibrationResult& projector,
                                  const std::vector<sl_projector::RigidTransform>& board_poses)
{
  Eigen::VectorXd p = Eigen::VectorXd::Zero(kBoards + 6 * static_cast<long>(board_poses.size()));
  getModel(camera, kCam, p);
  getModel(projector.projector, kProj, p);
  const sl_projector::RigidTransform inv = projector.pose.inverse();
  p.segment<3>(kPose) = vectorOf(inv.rotation);
  p.segment<3>(kPose + 3) = inv.translation;
  for (size_t j = 0; j < board_poses.size(); ++j)
  {
    p.segment<3>(kBoards + 6 * static_cast<long>(j)) = vectorOf(board_poses[j].rotation);
    p.segment<3>(kBoards + 6 * static_cast<long>(j) + 3) = board_poses[j].translation;
  }
  return p;
}

/// Which of the @p n parameters the joint refinement may change: not a given camera, nor the
/// distortion terms the options fix.
std::vector<bool> freeParameters(long n, bool camera_given, const FullCalibrationOptions& options)
{
  std::vector<bool> free(static_cast<size_t>(n), true);
  for (int i = 0; i < 9; ++i)
    free[static_cast<size_t>(kCam + i)] = !camera_given;
  free[kCam + 8] = free[kCam + 8] && !options.camera.fix_k3;
  if (options.camera.zero_tangential)
    free[kCam + 6] = free[kCam + 7] = false;
  free[kProj + 8] = !options.projector.fix_k3;
  if (options.projector.zero_tangential)
    free[kProj + 6] = free[kProj + 7] = false;
  return free;
}

/// Takes the refined parameters @p p, whose residuals are @p r (board views of @p corners corners
/// each, then @p prims), into @p out and @p board_poses, with the reprojection errors per view and
/// overall.
void applyRefinement(const Eigen::VectorXd& p, const Eigen::VectorXd& r, const std::vector<JointPrimitive>& prims,
                     size_t corners, std::vector<sl_projector::RigidTransform>& board_poses, FullCalibrationResult& out)
{
  setModel(p, kCam, out.camera.camera);
  setModel(p, kProj, out.projector.projector);
  sl_projector::RigidTransform pf;
  pf.rotation = rotationOf(p.segment<3>(kPose));
  pf.translation = p.segment<3>(kPose + 3);
  out.projector.pose = pf.inverse();
  long k = 0;
  double all = 0.0;
  for (size_t j = 0; j < board_poses.size(); ++j)
  {
    board_poses[j].rotation = rotationOf(p.segment<3>(kBoards + 6 * static_cast<long>(j)));
    board_poses[j].translation = p.segment<3>(kBoards + 6 * static_cast<long>(j) + 3);
    double s2 = 0.0;
    for (size_t i = 0; i < corners; ++i, k += 2)
      s2 += r(k) * r(k) + r(k + 1) * r(k + 1);
    all += s2;
    out.camera.view_rms[j] = std::sqrt(s2 / corners);
  }
  out.camera.rms = std::sqrt(all / std::max<size_t>(1, board_poses.size() * corners));
  out.camera.board_poses = board_poses;
  std::map<int, std::pair<double, int>> acc;
  double sp = 0.0;
  for (const JointPrimitive& q : prims)
  {
    const double e2 = r(k) * r(k) + r(k + 1) * r(k + 1);
    k += 2;
    sp += e2;
    acc[q.view].first += e2;
    ++acc[q.view].second;
  }
  out.projector.rms = std::sqrt(sp / std::max<size_t>(1, prims.size()));
  for (const auto& a : acc)
    out.projector.view_rms[static_cast<size_t>(a.first)] = std::sqrt(a.second.first / a.second.second);
  out.refined = true;
}

/// @p rig with the calibrated camera, projector and projector pose of @p out.
sl_projector::Rig calibratedRig(sl_projector::Rig rig, const FullCalibrationResult& out)
{
  rig.camera = out.camera.camera;
  rig.projector = out.projector.projector;
  rig.projector_pose = out.projector.pose;
  if (out.camera_lens.valid)
  {
    rig.camera_optics.focus_distance = out.camera_lens.lens.focus_distance;
    rig.camera_optics.f_number = out.camera_lens.lens.f_number;
  }
  try
  {
    rig.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw CalibrationError(std::string("the calibrated rig is not valid: ") + e.what());
  }
  return rig;
}
}  // namespace

std::vector<sl_projector::RigidTransform> FullCalibration::calibrateCameraStep(FullCalibrationResult& out) const
{
  if (camera_given_)
  {
    std::vector<sl_projector::RigidTransform> board_poses(board_views_.size());
    out.camera.camera = camera_;
    for (size_t i = 0; i < board_views_.size(); ++i)
    {
      double rms = 0.0;
      board_poses[i] = boardPose(camera_, board_, board_views_[i].corners, &rms);
      out.camera.view_rms.push_back(rms);
      out.camera_views.push_back(board_views_[i].name);
    }
    out.camera.board_poses = board_poses;
    return board_poses;
  }
  if (static_cast<int>(board_views_.size()) < options_.camera.min_views)
    throw CalibrationError("camera calibration needs >= " + std::to_string(options_.camera.min_views) +
                           " checkerboard views at different orientations, got " + std::to_string(board_views_.size()) +
                           " (or give the camera model, e.g. from ROS camera_calibration)");
  out.camera = calibrateCamera(board_views_, board_, cv::Size(rig_.camera.width, rig_.camera.height), options_.camera);
  out.camera_calibrated = true;
  for (const BoardView& v : board_views_)
    out.camera_views.push_back(v.name);
  return out.camera.board_poses;
}

std::vector<ProjectorCorrespondence> FullCalibration::planeCorrespondences(
    const sl_projector::Rig& rig, const std::vector<sl_projector::RigidTransform>& board_poses,
    FullCalibrationResult& out) const
{
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
        projectorCorrespondences(pattern, rig.camera, plane, v.samples, static_cast<int>(i));
    corr.insert(corr.end(), c.begin(), c.end());
    out.plane_views.push_back(v.name);
  }
  return corr;
}

void FullCalibration::refineJointly(const sl_projector::Rig& rig, const std::vector<ProjectorCorrespondence>& corr,
                                    std::vector<sl_projector::RigidTransform>& board_poses,
                                    FullCalibrationResult& out) const
{
  // The inliers of the projector fit, each on its plane: a board view's (refined with it) or a fixed one.
  std::vector<JointPrimitive> prims;
  for (size_t i = 0; i < corr.size(); ++i)
  {
    if (!out.projector.inlier[i])
      continue;
    const PlaneView& v = plane_views_[static_cast<size_t>(corr[i].view)];
    JointPrimitive q;
    q.board = v.board_view;
    if (v.board_view < 0)
      q.plane = planeAtDistance(rig, v.distance, options_.distance_planes);
    q.pixel = corr[i].pixel;
    q.projector = corr[i].projector;
    q.view = corr[i].view;
    prims.push_back(q);
  }
  Eigen::VectorXd p = initialParameters(rig.camera, out.projector, board_poses);
  const std::vector<bool> free = freeParameters(p.size(), camera_given_, options_);
  const std::vector<cv::Point3f> object = board_.objectPoints();
  const sl_projector::PinholeModel projector = out.projector.projector;
  LevenbergMarquardt lm;
  lm.max_iterations = options_.max_iterations;
  lm.minimize([&](const Eigen::VectorXd& q, Eigen::VectorXd& r)
              { jointResiduals(q, board_views_, object, prims, rig.camera, projector, r); },
              free, p);
  if (!(p.allFinite() && p(kCam) > 0.0 && p(kCam + 1) > 0.0 && p(kProj) > 0.0 && p(kProj + 1) > 0.0))
    return;  // the separate fits stand
  Eigen::VectorXd r;
  jointResiduals(p, board_views_, object, prims, rig.camera, projector, r);
  applyRefinement(p, r, prims, object.size(), board_poses, out);
}

std::vector<ImageResidual> FullCalibration::cornerResiduals(const FullCalibrationResult& out) const
{
  const std::vector<cv::Point3f> object = board_.objectPoints();
  std::vector<ImageResidual> res;
  for (size_t j = 0; j < board_views_.size() && j < out.camera.board_poses.size(); ++j)
  {
    const sl_projector::RigidTransform& pose = out.camera.board_poses[j];
    for (size_t i = 0; i < object.size() && i < board_views_[j].corners.size(); ++i)
    {
      const Eigen::Vector3d P(object[i].x, object[i].y, object[i].z);
      ImageResidual r;
      r.pixel = Eigen::Vector2d(board_views_[j].corners[i].x, board_views_[j].corners[i].y);
      r.residual = out.camera.camera.project(pose.rotation * P + pose.translation) - r.pixel;
      r.view = static_cast<int>(j);
      if (r.residual.allFinite())
        res.push_back(r);
    }
  }
  return res;
}

FullCalibrationResult FullCalibration::calibrate() const
{
  if (static_cast<int>(plane_views_.size()) < options_.projector.min_views)
    throw CalibrationError("full calibration needs >= " + std::to_string(options_.projector.min_views) +
                           " plane poses with the pattern (board + pattern image, or pattern image at a known "
                           "distance), got " +
                           std::to_string(plane_views_.size()));
  FullCalibrationResult out;
  // 1. Camera.
  std::vector<sl_projector::RigidTransform> board_poses = calibrateCameraStep(out);
  // 2. Planes in the camera frame, 3. projector correspondences and the projector.
  sl_projector::Rig rig = rig_;
  rig.camera = out.camera.camera;
  const std::vector<ProjectorCorrespondence> corr = planeCorrespondences(rig, board_poses, out);
  out.projector = calibrateProjector(corr, rig.projector.width, rig.projector.height, options_.projector);
  // 4. Everything together, from the separate fits.
  if (options_.joint_refinement)
    refineJointly(rig, corr, board_poses, out);
  // 5. The camera lens from the board edges' blur at their depths (final board poses).
  std::vector<BlurSample> blur;
  for (size_t i = 0; i < board_blur_.size() && i < out.camera.board_poses.size(); ++i)
  {
    const std::vector<BlurSample> b = blurAtDepth(board_blur_[i], out.camera.board_poses[i]);
    blur.insert(blur.end(), b.begin(), b.end());
  }
  out.camera_lens =
      fitLensOptics(blur, std::sqrt(out.camera.camera.fx * out.camera.camera.fy), rig.camera_optics.pixel_pitch);
  // 6. The rig with the calibrated models, pose and lens, and the corners' residuals.
  out.rig = calibratedRig(rig, out);
  out.camera_residuals = cornerResiduals(out);
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
  if (refined)
    o << "(after the joint refinement of camera, projector, pose and board poses)\n";
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
  o << camera_lens.summary("camera");
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

}  // namespace sl_calibration
