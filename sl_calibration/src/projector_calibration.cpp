#include "sl_calibration/projector_calibration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include <Eigen/Dense>
#include <opencv2/core.hpp>

#include "sl_calibration/optimizer.h"

namespace sl_calibration
{

std::vector<ProjectorCorrespondence> projectorCorrespondences(const sl_projector::Pattern& pattern,
                                                              const sl_projector::PinholeModel& camera,
                                                              const CalibrationPlane& plane,
                                                              const std::vector<PrimitiveSample>& samples, int view)
{
  std::vector<ProjectorCorrespondence> out;
  out.reserve(samples.size());
  const int rows = pattern.config().rows, cols = pattern.config().cols;
  for (const PrimitiveSample& s : samples)
  {
    if (s.row < 0 || s.col < 0 || s.row >= rows || s.col >= cols)
      continue;
    ProjectorCorrespondence c;
    if (!plane.intersect(camera.ray(Eigen::Vector2d(s.u, s.v)), c.point))
      continue;
    const cv::Point2d q = pattern.primitiveCentroid(s.row, s.col);
    c.projector = Eigen::Vector2d(q.x, q.y);
    c.pixel = Eigen::Vector2d(s.u, s.v);
    c.view = view;
    c.row = s.row;
    c.col = s.col;
    out.push_back(c);
  }
  return out;
}

std::vector<Eigen::Vector2d> projectorResiduals(const std::vector<ProjectorCorrespondence>& corr,
                                                const sl_projector::PinholeModel& projector,
                                                const sl_projector::RigidTransform& pose)
{
  const sl_projector::RigidTransform inv = pose.inverse();
  std::vector<Eigen::Vector2d> r;
  r.reserve(corr.size());
  for (const ProjectorCorrespondence& c : corr)
    r.push_back(projector.project(inv * c.point) - c.projector);
  return r;
}

namespace
{
/// Linear estimate: normalised DLT of x ~ P X, then P = K [R | t] (x_proj = R X + t).
bool linearEstimate(const std::vector<ProjectorCorrespondence>& corr, Eigen::Matrix3d& K, Eigen::Matrix3d& R,
                    Eigen::Vector3d& t)
{
  const size_t n = corr.size();
  if (n < 6)
    return false;
  Eigen::Vector3d c3 = Eigen::Vector3d::Zero();
  Eigen::Vector2d c2 = Eigen::Vector2d::Zero();
  for (const ProjectorCorrespondence& c : corr)
  {
    c3 += c.point;
    c2 += c.projector;
  }
  c3 /= static_cast<double>(n);
  c2 /= static_cast<double>(n);
  double s3 = 0.0, s2 = 0.0;
  for (const ProjectorCorrespondence& c : corr)
  {
    s3 += (c.point - c3).norm();
    s2 += (c.projector - c2).norm();
  }
  s3 = std::sqrt(3.0) * static_cast<double>(n) / s3;
  s2 = std::sqrt(2.0) * static_cast<double>(n) / s2;
  // The null vector of the 2n x 12 system, as the eigenvector of A^T A with the smallest eigenvalue
  // (well conditioned after the normalisation).
  Eigen::Matrix<double, 12, 12> AtA = Eigen::Matrix<double, 12, 12>::Zero();
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3d X = s3 * (corr[i].point - c3);
    const Eigen::Vector2d x = s2 * (corr[i].projector - c2);
    Eigen::Matrix<double, 4, 1> Xh;
    Xh << X, 1.0;
    Eigen::Matrix<double, 12, 1> r1, r2;
    r1 << Xh, Eigen::Matrix<double, 4, 1>::Zero(), -x.x() * Xh;
    r2 << Eigen::Matrix<double, 4, 1>::Zero(), Xh, -x.y() * Xh;
    AtA.noalias() += r1 * r1.transpose() + r2 * r2.transpose();
  }
  cv::Mat AtA_cv(12, 12, CV_64F), values, vectors;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      AtA_cv.at<double>(i, j) = AtA(i, j);
  if (!cv::eigen(AtA_cv, values, vectors))  // descending eigenvalues, eigenvectors as rows
    return false;
  if (values.at<double>(10) < 1e-12 * values.at<double>(0))
    return false;  // coplanar points: the projection is not determined
  Eigen::Matrix<double, 12, 1> p;
  for (int i = 0; i < 12; ++i)
    p(i) = vectors.at<double>(11, i);
  Eigen::Matrix<double, 3, 4> Pn;
  Pn << p.segment<4>(0).transpose(), p.segment<4>(4).transpose(), p.segment<4>(8).transpose();
  // Undo the normalisation: P = T2^-1 Pn T3.
  Eigen::Matrix3d T2 = Eigen::Matrix3d::Identity();
  T2(0, 0) = T2(1, 1) = s2;
  T2.block<2, 1>(0, 2) = -s2 * c2;
  Eigen::Matrix4d T3 = Eigen::Matrix4d::Identity();
  T3.block<3, 3>(0, 0) *= s3;
  T3.block<3, 1>(0, 3) = -s3 * c3;
  Eigen::Matrix<double, 3, 4> P = T2.inverse() * Pn * T3;
  Eigen::Matrix3d M = P.block<3, 3>(0, 0);
  if (M.determinant() < 0.0)
  {
    P = -P;
    M = -M;
  }
  // RQ decomposition M = K R by Gram-Schmidt from the last row up (K upper triangular, positive diagonal).
  K.setZero();
  R.setZero();
  Eigen::Vector3d r3 = M.row(2).transpose();
  K(2, 2) = r3.norm();
  r3 /= K(2, 2);
  Eigen::Vector3d r2 = M.row(1).transpose();
  K(1, 2) = r2.dot(r3);
  r2 -= K(1, 2) * r3;
  K(1, 1) = r2.norm();
  r2 /= K(1, 1);
  Eigen::Vector3d r1 = M.row(0).transpose();
  K(0, 2) = r1.dot(r3);
  K(0, 1) = r1.dot(r2);
  r1 -= K(0, 2) * r3 + K(0, 1) * r2;
  K(0, 0) = r1.norm();
  r1 /= K(0, 0);
  R.row(0) = r1.transpose();
  R.row(1) = r2.transpose();
  R.row(2) = r3.transpose();
  if (R.determinant() < 0.0)
    return false;
  t = K.inverse() * P.col(3);
  K /= K(2, 2);
  return K.allFinite() && R.allFinite() && t.allFinite() && K(0, 0) > 0.0 && K(1, 1) > 0.0;
}

Eigen::Matrix3d rotationFromVector(const Eigen::Vector3d& w)
{
  const double a = w.norm();
  if (a < 1e-15)
    return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

Eigen::Vector3d vectorFromRotation(const Eigen::Matrix3d& R)
{
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// Parameter layout: fx fy cx cy k1 k2 p1 p2 k3 | w(3) t(3): x_proj = R(w) X + t.
constexpr int kParams = 15;

void unpack(const Eigen::VectorXd& p, int width, int height, sl_projector::PinholeModel& m, Eigen::Matrix3d& R,
            Eigen::Vector3d& t)
{
  m.width = width;
  m.height = height;
  m.fx = p(0);
  m.fy = p(1);
  m.cx = p(2);
  m.cy = p(3);
  for (int i = 0; i < 5; ++i)
    m.dist[static_cast<size_t>(i)] = p(4 + i);
  R = rotationFromVector(p.segment<3>(9));
  t = p.segment<3>(12);
}

void fit(const std::vector<ProjectorCorrespondence>& corr, int width, int height, const std::vector<bool>& free,
         int iterations, Eigen::VectorXd& params)
{
  auto residuals = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r)
  {
    sl_projector::PinholeModel m;
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    unpack(p, width, height, m, R, t);
    r.resize(static_cast<long>(2 * corr.size()));
    for (size_t i = 0; i < corr.size(); ++i)
    {
      const Eigen::Vector3d q = R * corr[i].point + t;
      Eigen::Vector2d e;
      if (q.z() <= 1e-6)
        e = Eigen::Vector2d(1e3, 1e3);
      else
        e = m.project(q) - corr[i].projector;
      r(static_cast<long>(2 * i)) = e.x();
      r(static_cast<long>(2 * i + 1)) = e.y();
    }
  };
  LevenbergMarquardt lm;
  lm.max_iterations = iterations;
  lm.minimize(residuals, free, params);
}
}  // namespace

ProjectorCalibrationResult calibrateProjector(const std::vector<ProjectorCorrespondence>& correspondences, int width,
                                              int height, const ProjectorCalibrationOptions& options)
{
  if (width <= 0 || height <= 0)
    throw CalibrationError("projector calibration: the projector frame size is not set");
  std::map<int, int> per_view;
  for (const ProjectorCorrespondence& c : correspondences)
    ++per_view[c.view];
  std::vector<ProjectorCorrespondence> corr;
  std::vector<size_t> source;  // index of each used correspondence in the input
  std::string weak;
  int views = 0;
  for (const auto& v : per_view)
  {
    if (v.second >= options.min_points_per_view)
      ++views;
    else
      weak += " view " + std::to_string(v.first) + " has only " + std::to_string(v.second) + " decoded primitives;";
  }
  for (size_t i = 0; i < correspondences.size(); ++i)
    if (per_view[correspondences[i].view] >= options.min_points_per_view)
    {
      corr.push_back(correspondences[i]);
      source.push_back(i);
    }
  if (views < options.min_views)
    throw CalibrationError("projector calibration needs >= " + std::to_string(options.min_views) +
                           " plane poses with the decoded pattern (at least " +
                           std::to_string(options.min_points_per_view) + " primitives each), got " +
                           std::to_string(views) + (weak.empty() ? std::string() : ":" + weak));

  // Linear estimate inside RANSAC: wrong decodes (a primitive taken for another) must not bias it.
  Eigen::Matrix3d K, R;
  Eigen::Vector3d t;
  std::vector<ProjectorCorrespondence> consensus;
  {
    std::mt19937 rng(12345);  // deterministic: the same data give the same calibration
    std::uniform_int_distribution<size_t> pick(0, corr.size() - 1);
    const double gate = std::max(5.0, 2.0 * options.outlier_px);
    size_t best = 0;
    for (int it = 0; it < 200; ++it)
    {
      std::vector<ProjectorCorrespondence> sample;
      std::set<int> sample_views;
      for (int k = 0; k < 8; ++k)
      {
        sample.push_back(corr[pick(rng)]);
        sample_views.insert(sample.back().view);
      }
      if (sample_views.size() < 2)
        continue;
      Eigen::Matrix3d Ks, Rs;
      Eigen::Vector3d ts;
      if (!linearEstimate(sample, Ks, Rs, ts))
        continue;
      std::vector<ProjectorCorrespondence> in;
      for (const ProjectorCorrespondence& c : corr)
      {
        const Eigen::Vector3d q = Ks * (Rs * c.point + ts);
        if (q.z() > 0.0 && (Eigen::Vector2d(q.x() / q.z(), q.y() / q.z()) - c.projector).norm() < gate)
          in.push_back(c);
      }
      if (in.size() > best)
      {
        best = in.size();
        consensus.swap(in);
        if (best > 0.9 * corr.size())
          break;
      }
    }
  }
  if (consensus.size() < 12 || !linearEstimate(consensus, K, R, t))
    throw CalibrationError(
        "projector calibration: no consistent linear estimate (are all plane poses the same plane, "
        "or is most of the pattern decoded wrongly?)");

  Eigen::VectorXd params = Eigen::VectorXd::Zero(kParams);
  params << K(0, 0), K(1, 1), K(0, 2), K(1, 2), 0, 0, 0, 0, 0, vectorFromRotation(R), t;
  std::vector<bool> free(kParams, true);
  free[8] = !options.fix_k3;
  if (options.zero_tangential)
    free[6] = free[7] = false;
  // Pinhole first, then with distortion, on the consensus set.
  std::vector<bool> pinhole(free);
  for (int i = 4; i < 9; ++i)
    pinhole[static_cast<size_t>(i)] = false;
  fit(consensus, width, height, pinhole, options.max_iterations, params);
  fit(consensus, width, height, free, options.max_iterations, params);

  // Trim outliers (wrong decodes, points off the plane) against a robust scale and fit again, until
  // the inlier set settles.
  sl_projector::PinholeModel m;
  sl_projector::RigidTransform pose;
  std::vector<ProjectorCorrespondence> inliers;
  ProjectorCalibrationResult out;
  std::vector<bool> keep;
  for (int round = 0; round < 4; ++round)
  {
    unpack(params, width, height, m, R, t);
    pose.rotation = R.transpose();
    pose.translation = -R.transpose() * t;
    const std::vector<Eigen::Vector2d> res = projectorResiduals(corr, m, pose);
    std::vector<double> norms;
    for (const Eigen::Vector2d& e : res)
      norms.push_back(std::isfinite(e.x()) ? e.norm() : 1e9);
    std::vector<double> sorted(norms);
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const double limit = std::max(options.outlier_px, 4.0 * median);
    std::vector<bool> k(corr.size());
    for (size_t i = 0; i < corr.size(); ++i)
      k[i] = norms[i] <= limit;
    if (k == keep)
      break;
    keep = k;
    inliers.clear();
    for (size_t i = 0; i < corr.size(); ++i)
      if (keep[i])
        inliers.push_back(corr[i]);
    if (inliers.size() < 12)
      throw CalibrationError("projector calibration failed: almost every correspondence is an outlier");
    fit(inliers, width, height, free, options.max_iterations, params);
  }
  out.inlier.assign(correspondences.size(), false);
  for (size_t i = 0; i < corr.size(); ++i)
    out.inlier[source[i]] = keep[i];
  out.outliers = static_cast<int>(correspondences.size() - inliers.size());
  unpack(params, width, height, m, R, t);
  pose.rotation = R.transpose();
  pose.translation = -R.transpose() * t;
  if (!(m.fx > 0.0 && m.fy > 0.0) || !params.allFinite())
    throw CalibrationError("projector calibration failed: the fit did not converge to a valid projector");

  out.projector = m;
  out.pose = pose;
  const std::vector<Eigen::Vector2d> res = projectorResiduals(inliers, m, pose);
  std::map<int, std::pair<double, int>> acc;
  double s = 0.0;
  for (size_t i = 0; i < inliers.size(); ++i)
  {
    s += res[i].squaredNorm();
    acc[inliers[i].view].first += res[i].squaredNorm();
    ++acc[inliers[i].view].second;
  }
  out.points = static_cast<int>(inliers.size());
  out.rms = std::sqrt(s / std::max<size_t>(1, inliers.size()));
  const int max_view = per_view.empty() ? -1 : per_view.rbegin()->first;
  out.view_rms.assign(static_cast<size_t>(max_view + 1), 0.0);
  out.view_points.assign(static_cast<size_t>(max_view + 1), 0);
  for (const auto& a : acc)
  {
    out.view_rms[static_cast<size_t>(a.first)] = std::sqrt(a.second.first / a.second.second);
    out.view_points[static_cast<size_t>(a.first)] = a.second.second;
  }
  if (out.rms > options.max_rms)
    throw CalibrationError("projector calibration failed: the reprojection error is " + fixed(out.rms, 2) +
                           " px rms (more than " + fixed(options.max_rms, 2) +
                           "): the pattern was decoded wrongly or the planes are wrong. Is the rig file far from "
                           "the real rig (raise the epipolar tolerance)? Is the board flat on the plane, and the "
                           "pattern on the same plane?");
  return out;
}

}  // namespace sl_calibration
