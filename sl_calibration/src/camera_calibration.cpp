#include "sl_calibration/camera_calibration.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

namespace sl_calibration
{

std::vector<cv::Point3f> Board::objectPoints() const
{
  std::vector<cv::Point3f> p;
  p.reserve(static_cast<size_t>(rows * cols));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      p.emplace_back(static_cast<float>(c * square), static_cast<float>(r * square), 0.f);
  return p;
}

void Board::validate() const
{
  if (cols < 2 || rows < 2)
    throw std::invalid_argument("board: needs at least 2 x 2 inner corners, got " + std::to_string(cols) + "x" +
                                std::to_string(rows));
  if (cols == rows)
    throw std::invalid_argument(
        "board: use a board with different numbers of inner corners along its two sides "
        "(got " +
        std::to_string(cols) + "x" + std::to_string(rows) + ")");
  if (!(square > 0.0) || !std::isfinite(square))
    throw std::invalid_argument("square: must be > 0 m");
  if (square > 1.0)
    throw std::invalid_argument("square: " + std::to_string(square) + " is not metres (mm given?)");
}

Board parseBoardSize(const std::string& text, double square)
{
  Board b;
  const size_t x = text.find_first_of("xX");
  try
  {
    if (x == std::string::npos)
      throw std::invalid_argument("");
    size_t used = 0;
    b.cols = std::stoi(text.substr(0, x), &used);
    if (used != x)
      throw std::invalid_argument("");
    const std::string r = text.substr(x + 1);
    b.rows = std::stoi(r, &used);
    if (used != r.size())
      throw std::invalid_argument("");
  }
  catch (const std::exception&)
  {
    throw std::invalid_argument("board: expected COLSxROWS inner corners (e.g. 8x5), got '" + text + "'");
  }
  b.square = square;
  b.validate();
  return b;
}

bool findBoardCorners(const cv::Mat& grey, const Board& board, std::vector<cv::Point2f>& corners)
{
  corners.clear();
  if (grey.empty() || grey.type() != CV_8UC1)
    return false;
  const cv::Size size(board.cols, board.rows);
  if (!cv::findChessboardCorners(grey, size, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
  {
    corners.clear();
    return false;
  }
  // Sub-pixel refinement with a window of about half the smallest corner spacing.
  double spacing = 1e9;
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c + 1 < board.cols; ++c)
    {
      const cv::Point2f d =
          corners[static_cast<size_t>(r * board.cols + c + 1)] - corners[static_cast<size_t>(r * board.cols + c)];
      spacing = std::min(spacing, static_cast<double>(std::hypot(d.x, d.y)));
    }
  for (int r = 0; r + 1 < board.rows; ++r)
    for (int c = 0; c < board.cols; ++c)
    {
      const cv::Point2f d =
          corners[static_cast<size_t>((r + 1) * board.cols + c)] - corners[static_cast<size_t>(r * board.cols + c)];
      spacing = std::min(spacing, static_cast<double>(std::hypot(d.x, d.y)));
    }
  const int half = std::max(2, std::min(11, static_cast<int>(spacing * 0.4)));
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  return true;
}

namespace
{
sl_projector::RigidTransform fromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec)
{
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  sl_projector::RigidTransform t;
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
      t.rotation(i, j) = R.at<double>(i, j);
    t.translation(i) = tvec.at<double>(i);
  }
  return t;
}

double viewRms(const std::vector<cv::Point3f>& object, const std::vector<cv::Point2f>& image, const cv::Mat& rvec,
               const cv::Mat& tvec, const cv::Mat& K, const cv::Mat& D)
{
  std::vector<cv::Point2f> projected;
  cv::projectPoints(object, rvec, tvec, K, D, projected);
  double s = 0.0;
  for (size_t i = 0; i < image.size(); ++i)
  {
    const cv::Point2f d = projected[i] - image[i];
    s += d.x * d.x + d.y * d.y;
  }
  return image.empty() ? 0.0 : std::sqrt(s / image.size());
}

cv::Mat distCoeffs(const sl_projector::PinholeModel& m)
{
  return (cv::Mat_<double>(1, 5) << m.dist[0], m.dist[1], m.dist[2], m.dist[3], m.dist[4]);
}
}  // namespace

CameraCalibrationResult calibrateCamera(const std::vector<BoardView>& views, const Board& board, cv::Size image_size,
                                        const CameraCalibrationOptions& options)
{
  board.validate();
  if (static_cast<int>(views.size()) < options.min_views)
    throw CalibrationError("camera calibration needs >= " + std::to_string(options.min_views) +
                           " checkerboard views at different orientations, got " + std::to_string(views.size()));
  const std::vector<cv::Point3f> object = board.objectPoints();
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const BoardView& v : views)
  {
    if (v.corners.size() != object.size())
      throw CalibrationError(v.name + ": has " + std::to_string(v.corners.size()) + " corners, the board has " +
                             std::to_string(object.size()));
    object_points.push_back(object);
    image_points.push_back(v.corners);
  }
  int flags = 0;
  if (options.fix_k3)
    flags |= cv::CALIB_FIX_K3;
  if (options.zero_tangential)
    flags |= cv::CALIB_ZERO_TANGENT_DIST;
  cv::Mat K, D;
  std::vector<cv::Mat> rvecs, tvecs;
  double rms = 0.0;
  try
  {
    rms = cv::calibrateCamera(object_points, image_points, image_size, K, D, rvecs, tvecs, flags,
                              cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
  }
  catch (const cv::Exception& e)
  {
    throw CalibrationError(std::string("camera calibration failed (OpenCV): ") + e.what());
  }
  if (!std::isfinite(rms) || !cv::checkRange(K) || !cv::checkRange(D))
    throw CalibrationError("camera calibration failed: the solution is not finite (are the views too similar?)");

  CameraCalibrationResult res;
  res.rms = rms;
  res.camera.width = image_size.width;
  res.camera.height = image_size.height;
  res.camera.fx = K.at<double>(0, 0);
  res.camera.fy = K.at<double>(1, 1);
  res.camera.cx = K.at<double>(0, 2);
  res.camera.cy = K.at<double>(1, 2);
  cv::Mat d = D.reshape(1, 1);
  for (int i = 0; i < 5; ++i)
    res.camera.dist[static_cast<size_t>(i)] = i < d.cols ? d.at<double>(0, i) : 0.0;
  for (size_t i = 0; i < views.size(); ++i)
  {
    res.view_rms.push_back(viewRms(object, views[i].corners, rvecs[i], tvecs[i], K, D));
    res.board_poses.push_back(fromRvecTvec(rvecs[i], tvecs[i]));
  }
  if (!(res.camera.fx > 0.0 && res.camera.fy > 0.0))
    throw CalibrationError("camera calibration failed: non-positive focal length");
  return res;
}

sl_projector::RigidTransform boardPose(const sl_projector::PinholeModel& camera, const Board& board,
                                       const std::vector<cv::Point2f>& corners, double* rms)
{
  const std::vector<cv::Point3f> object = board.objectPoints();
  if (corners.size() != object.size())
    throw CalibrationError("board pose: " + std::to_string(corners.size()) + " corners given, the board has " +
                           std::to_string(object.size()));
  const cv::Mat K(camera.cameraMatrix());
  const cv::Mat D = distCoeffs(camera);
  cv::Mat rvec, tvec;
  bool ok = false;
  try
  {
    ok = cv::solvePnP(object, corners, K, D, rvec, tvec, false, cv::SOLVEPNP_ITERATIVE);
  }
  catch (const cv::Exception& e)
  {
    throw CalibrationError(std::string("board pose failed (OpenCV): ") + e.what());
  }
  if (!ok)
    throw CalibrationError("board pose: solvePnP failed");
  if (rms)
    *rms = viewRms(object, corners, rvec, tvec, K, D);
  return fromRvecTvec(rvec, tvec);
}

CalibrationPlane planeOfBoard(const sl_projector::RigidTransform& board_in_camera)
{
  CalibrationPlane p;
  p.normal = board_in_camera.rotation.col(2).normalized();
  p.offset = p.normal.dot(board_in_camera.translation);
  if (p.offset < 0.0)
  {
    p.normal = -p.normal;
    p.offset = -p.offset;
  }
  return p;
}

namespace
{
std::vector<double> matrixData(const YAML::Node& root, const std::string& key, size_t count, const std::string& path)
{
  const YAML::Node n = root[key];
  if (!n)
    throw CalibrationError(path + ": " + key + ": missing");
  const YAML::Node data = n["data"];
  if (!data || !data.IsSequence())
    throw CalibrationError(path + ": " + key + ".data: missing or not a list");
  if (count > 0 && data.size() != count)
    throw CalibrationError(path + ": " + key + ".data: has " + std::to_string(data.size()) + " numbers, expected " +
                           std::to_string(count));
  std::vector<double> out;
  for (const YAML::Node& x : data)
    out.push_back(x.as<double>());
  return out;
}
}  // namespace

sl_projector::PinholeModel loadCameraInfo(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw CalibrationError(path + ": cannot open the camera_info file");
  sl_projector::PinholeModel m;
  try
  {
    const YAML::Node root = YAML::Load(in);
    if (!root || !root.IsMap())
      throw CalibrationError(path + ": not a camera_info YAML file (expected a mapping)");
    if (!root["image_width"] || !root["image_height"])
      throw CalibrationError(path + ": image_width / image_height: missing");
    m.width = root["image_width"].as<int>();
    m.height = root["image_height"].as<int>();
    const std::vector<double> K = matrixData(root, "camera_matrix", 9, path);
    m.fx = K[0];
    m.cx = K[2];
    m.fy = K[4];
    m.cy = K[5];
    if (K[1] != 0.0)
      throw CalibrationError(path + ": camera_matrix: skew is not supported");
    const std::string model = root["distortion_model"] ? root["distortion_model"].as<std::string>() : "plumb_bob";
    if (model != "plumb_bob" && model != "rational_polynomial")
      throw CalibrationError(path + ": distortion_model: '" + model + "' is not supported (plumb_bob)");
    const std::vector<double> D = matrixData(root, "distortion_coefficients", 0, path);
    if (D.size() < 4 || D.size() > 8)
      throw CalibrationError(path + ": distortion_coefficients.data: has " + std::to_string(D.size()) +
                             " numbers, expected 4 or 5 (plumb_bob)");
    if (D.size() > 5)
      for (size_t i = 5; i < D.size(); ++i)
        if (D[i] != 0.0)
          throw CalibrationError(path + ": distortion_coefficients.data: only plumb_bob (k1 k2 p1 p2 k3) is supported");
    for (size_t i = 0; i < 5; ++i)
      m.dist[i] = i < D.size() ? D[i] : 0.0;
  }
  catch (const YAML::Exception& e)
  {
    throw CalibrationError(path + ": not valid camera_info YAML: " + e.what());
  }
  if (!(m.width > 0 && m.height > 0 && m.fx > 0.0 && m.fy > 0.0))
    throw CalibrationError(path + ": camera_matrix / image size: not a calibrated camera (zero focal length or size)");
  return m;
}

std::string cameraInfoYaml(const sl_projector::PinholeModel& c, const std::string& camera_name)
{
  std::ostringstream o;
  o.precision(12);
  auto list = [&](const std::vector<double>& v)
  {
    o << "[";
    for (size_t i = 0; i < v.size(); ++i)
      o << (i ? ", " : "") << v[i];
    o << "]";
  };
  o << "image_width: " << c.width << "\nimage_height: " << c.height << "\ncamera_name: " << camera_name
    << "\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: ";
  list({ c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0 });
  o << "\ndistortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: ";
  list({ c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4] });
  o << "\nrectification_matrix:\n  rows: 3\n  cols: 3\n  data: ";
  list({ 1, 0, 0, 0, 1, 0, 0, 0, 1 });
  o << "\nprojection_matrix:\n  rows: 3\n  cols: 4\n  data: ";
  list({ c.fx, 0.0, c.cx, 0.0, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0 });
  o << "\n";
  return o.str();
}

void saveCameraInfo(const sl_projector::PinholeModel& camera, const std::string& path, const std::string& camera_name)
{
  std::ofstream out(path);
  if (!out)
    throw CalibrationError(path + ": cannot write the camera_info file");
  out << cameraInfoYaml(camera, camera_name);
  if (!out)
    throw CalibrationError(path + ": write failed");
}

}  // namespace sl_calibration
