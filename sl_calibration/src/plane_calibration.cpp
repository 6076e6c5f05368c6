#include "sl_calibration/plane_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include <Eigen/Dense>

namespace sl_calibration
{

namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v)
{
  if (v.empty())
    return kNaN;
  const size_t n = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(n), v.end());
  if (v.size() % 2 == 1)
    return v[n];
  const double upper = v[n];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<long>(n)));
}

double rmsOf(const std::vector<double>& r)
{
  double s = 0.0;
  int n = 0;
  for (double x : r)
    if (std::isfinite(x))
    {
      s += x * x;
      ++n;
    }
  return n > 0 ? std::sqrt(s / n) : 0.0;
}

std::string mm(double metres, int digits = 2)
{
  return fixed(1000.0 * metres, digits);
}
}  // namespace

DistanceReference parseDistanceReference(const std::string& name)
{
  if (name == "camera")
    return DistanceReference::Camera;
  if (name == "edge")
    return DistanceReference::Edge;
  throw std::invalid_argument("distance reference must be 'camera' or 'edge', got '" + name + "'");
}

PlaneNormal parsePlaneNormal(const std::string& name)
{
  if (name == "robot")
    return PlaneNormal::Robot;
  if (name == "camera")
    return PlaneNormal::Camera;
  throw std::invalid_argument("plane normal must be 'robot' or 'camera', got '" + name + "'");
}

void PlaneCalibrationOptions::validate() const
{
  if (min_distances < 3)
    throw std::invalid_argument("min_distances: must be >= 3 (the rational model has 3 parameters), got " +
                                std::to_string(min_distances));
  if (!(same_distance > 0.0 && same_distance < 0.1))
    throw std::invalid_argument("same_distance: must be in (0, 0.1) m");
  if (!(max_rational_rms > 0.0))
    throw std::invalid_argument("max_rational_rms: must be > 0 m");
  if (normal == PlaneNormal::Camera && reference != DistanceReference::Camera)
    throw std::invalid_argument("reference: a plane perpendicular to the camera axis is measured from the camera");
}

CalibrationPlane planeAtDistance(const sl_projector::Rig& rig, double distance, const PlaneCalibrationOptions& options)
{
  if (!std::isfinite(distance) || distance <= 0.0)
    throw std::invalid_argument("the plane distance must be finite and > 0 m, got " + std::to_string(distance));
  CalibrationPlane plane;
  if (options.normal == PlaneNormal::Camera)
  {
    plane.normal = Eigen::Vector3d::UnitZ();
    plane.offset = distance;
    return plane;
  }
  // The plane x = d of the mount's parent frame, in the camera optical frame.
  const sl_projector::RigidTransform cam = rig.mount.cameraOpticalInParent();
  const double d = options.reference == DistanceReference::Camera ? cam.translation.x() + distance : distance;
  plane.normal = cam.rotation.transpose() * Eigen::Vector3d::UnitX();
  plane.offset = d - cam.translation.x();
  if (plane.normal.z() <= 0.1)
    throw std::invalid_argument(
        "the camera does not look along the robot's x axis (mount.rpy): a plane "
        "perpendicular to the robot is not in front of it");
  if (plane.offset <= 0.0)
    throw std::invalid_argument("a plane at " + fixed(distance, 3) + " m from the edge is behind the camera");
  return plane;
}

double depthOnPlane(const sl_projector::PinholeModel& camera, const CalibrationPlane& plane, double u, double v)
{
  Eigen::Vector3d p;
  if (!plane.intersect(camera.ray(Eigen::Vector2d(u, v)), p))
    return kNaN;
  return p.z();
}

sl_projector::DepthModel fitLinear(const std::vector<double>& u, const std::vector<double>& depth)
{
  sl_projector::DepthModel m;
  const size_t n = u.size();
  if (n < 2 || depth.size() != n)
    return m;
  const double mu = std::accumulate(u.begin(), u.end(), 0.0) / n;
  const double mz = std::accumulate(depth.begin(), depth.end(), 0.0) / n;
  double suu = 0.0, suz = 0.0;
  for (size_t i = 0; i < n; ++i)
  {
    suu += (u[i] - mu) * (u[i] - mu);
    suz += (u[i] - mu) * (depth[i] - mz);
  }
  if (suu < 1e-12)
    return m;
  m.b = suz / suu;
  m.a = mz - m.b * mu;
  m.c = 0.0;
  std::vector<double> r(n);
  for (size_t i = 0; i < n; ++i)
    r[i] = m.depth(u[i]) - depth[i];
  m.rms = rmsOf(r);
  m.valid = true;
  return m;
}

namespace
{
/// The rational model in t = (u - centre) / scale, where the denominator stays far from its pole:
/// depth = (p0 + p1 t) / (1 + p2 t), fitted to the points (t, depth).
struct RationalInT
{
  const std::vector<double>& t;
  const std::vector<double>& depth;

  /// The algebraic solution of p0 + p1 t - p2 t z = z (exact for three points); false if degenerate.
  bool algebraic(Eigen::Vector3d& p) const
  {
    const size_t n = t.size();
    Eigen::MatrixXd M(n, 3);
    Eigen::VectorXd rhs(n);
    for (size_t i = 0; i < n; ++i)
    {
      M(static_cast<long>(i), 0) = 1.0;
      M(static_cast<long>(i), 1) = t[i];
      M(static_cast<long>(i), 2) = -t[i] * depth[i];
      rhs(static_cast<long>(i)) = depth[i];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(M);
    if (qr.rank() < 3)
      return false;
    p = qr.solve(rhs);
    return true;
  }

  /// The residuals model - depth of @p q in @p r; returns their squared norm.
  double residuals(const Eigen::Vector3d& q, Eigen::VectorXd& r) const
  {
    const size_t n = t.size();
    r.resize(static_cast<long>(n));
    for (size_t i = 0; i < n; ++i)
    {
      const double den = 1.0 + q(2) * t[i];
      r(static_cast<long>(i)) = (q(0) + q(1) * t[i]) / den - depth[i];
    }
    return r.squaredNorm();
  }

  /// The denominator is linear in t: positive at both ends means positive over the whole range.
  static bool poleFree(const Eigen::Vector3d& q) { return 1.0 + q(2) * -1.0 > 1e-3 && 1.0 + q(2) * 1.0 > 1e-3; }

  /// Gauss-Newton with step halving on the depth residual, from @p p whose residuals are @p r and
  /// cost @p cost (all three updated).
  void refine(Eigen::Vector3d& p, Eigen::VectorXd& r, double& cost) const
  {
    const size_t n = t.size();
    for (int it = 0; it < 20; ++it)
    {
      Eigen::MatrixXd J(n, 3);
      for (size_t i = 0; i < n; ++i)
      {
        const double den = 1.0 + p(2) * t[i];
        const double f = (p(0) + p(1) * t[i]) / den;
        J(static_cast<long>(i), 0) = 1.0 / den;
        J(static_cast<long>(i), 1) = t[i] / den;
        J(static_cast<long>(i), 2) = -t[i] * f / den;
      }
      const Eigen::Vector3d step = J.colPivHouseholderQr().solve(-r);
      double lambda = 1.0;
      bool improved = false;
      for (int h = 0; h < 10; ++h, lambda *= 0.5)
      {
        const Eigen::Vector3d q = p + lambda * step;
        Eigen::VectorXd rq;
        if (!poleFree(q) || !q.allFinite())
          continue;
        const double c = residuals(q, rq);
        if (c <= cost)
        {
          improved = cost - c > 1e-18;
          p = q;
          r = rq;
          cost = c;
          break;
        }
      }
      if (!improved || step.norm() < 1e-12)
        break;
    }
  }
};
}  // namespace

sl_projector::DepthModel fitRational(const std::vector<double>& u, const std::vector<double>& depth)
{
  sl_projector::DepthModel m;
  const size_t n = u.size();
  if (n < 3 || depth.size() != n)
    return m;
  // Work in t = (u - centre) / scale, where the denominator stays far from its pole.
  const auto range = std::minmax_element(u.begin(), u.end());
  const double centre = 0.5 * (*range.first + *range.second);
  const double scale = std::max(1.0, 0.5 * (*range.second - *range.first));
  if (*range.second - *range.first < 1e-6)
    return m;
  std::vector<double> t(n);
  for (size_t i = 0; i < n; ++i)
    t[i] = (u[i] - centre) / scale;

  // The algebraic solution, then (when over-determined) least squares on the depth residual.
  const RationalInT model{ t, depth };
  Eigen::Vector3d p;
  if (!model.algebraic(p) || !RationalInT::poleFree(p) || !p.allFinite())
    return m;
  Eigen::VectorXd r;
  double cost = model.residuals(p, r);
  if (n > 3)
    model.refine(p, r, cost);

  // Back to the image column: z = ((A s - B c) + B u) / ((s - C c) + C u), normalised to 1 + c u.
  const double num0 = p(0) * scale - p(1) * centre;
  const double den0 = scale - p(2) * centre;
  if (std::abs(den0) < 1e-12 * (scale + std::abs(p(2) * centre)))
    return m;  // the pole sits exactly at u = 0: not representable as (a + b u) / (1 + c u)
  m.a = num0 / den0;
  m.b = p(1) / den0;
  m.c = p(2) / den0;
  m.rms = std::sqrt(cost / n);
  m.valid = std::isfinite(m.a) && std::isfinite(m.b) && std::isfinite(m.c);
  return m;
}

PlaneCalibration::PlaneCalibration(const sl_projector::Rig& rig, const PlaneCalibrationOptions& options)
  : rig_(rig), options_(options)
{
  options_.validate();
  rig_.validate();
}

int PlaneCalibration::groupFor(double distance)
{
  for (size_t i = 0; i < groups_.size(); ++i)
    if (std::abs(groups_[i].distance - distance) < options_.same_distance)
      return static_cast<int>(i);
  Group g;
  g.distance = distance;
  try
  {
    g.plane = planeAtDistance(rig_, distance, options_);
  }
  catch (const std::invalid_argument& e)
  {
    throw CalibrationError(e.what());
  }
  g.pixels.resize(static_cast<size_t>(rig_.pattern.rows * rig_.pattern.cols));
  groups_.push_back(std::move(g));
  return static_cast<int>(groups_.size()) - 1;
}

int PlaneCalibration::addSamples(double distance, const std::vector<PrimitiveSample>& samples,
                                 const std::string& source)
{
  if (!std::isfinite(distance) || distance <= 0.0)
  {
    std::ostringstream o;
    o << (source.empty() ? std::string("image") : source)
      << ": the plane distance must be a positive number of metres, got " << distance;
    throw CalibrationError(o.str());
  }
  if (distance > 20.0)
  {
    std::ostringstream o;
    o << (source.empty() ? std::string("image") : source) << ": a plane distance of " << distance
      << " is not metres (mm given?)";
    throw CalibrationError(o.str());
  }
  Group& g = groups_[static_cast<size_t>(groupFor(distance))];
  ++g.images;
  ++images_;
  int added = 0;
  const int rows = rig_.pattern.rows, cols = rig_.pattern.cols;
  for (const PrimitiveSample& s : samples)
  {
    if (s.row < 0 || s.col < 0 || s.row >= rows || s.col >= cols || !std::isfinite(s.u) || !std::isfinite(s.v))
      continue;
    g.pixels[static_cast<size_t>(s.row * cols + s.col)].emplace_back(s.u, s.v);
    ++added;
  }
  return added;
}

int PlaneCalibration::addImage(double distance, const sl_decoder::DecodeResult& result, const std::string& source)
{
  return addSamples(distance, decodedSamples(result), source);
}

std::vector<double> PlaneCalibration::distances() const
{
  std::vector<double> d;
  for (const Group& g : groups_)
    d.push_back(g.distance);
  std::sort(d.begin(), d.end());
  return d;
}

void PlaneCalibration::clear()
{
  groups_.clear();
  images_ = 0;
}

namespace
{
/// The distances of a calibration for messages: "0.700 m (2 images, 828 primitives), ...".
std::string listDistances(const std::vector<DistanceSummary>& distances)
{
  std::string out;
  for (const DistanceSummary& s : distances)
    out += (out.empty() ? "" : ", ") + fixed(s.distance, 3) + " m (" + std::to_string(s.images) + " image" +
           (s.images == 1 ? "" : "s") + ", " + std::to_string(s.primitives) + " primitives)";
  return out;
}

/// The residuals of the calibrated primitives (model - target, m), per distance and overall.
struct Residuals
{
  explicit Residuals(size_t distances) : linear(distances), rational(distances) {}
  std::vector<std::vector<double>> linear, rational;  // per distance
  std::vector<double> all_linear, all_rational;
};

/**
 * The rational fit of primitive @p f on the distances @p seen_at (indices into f.u, f.depth). When
 * it is invalid or leaves more than max_rational_rms and there are more distances than needed, one
 * inconsistent distance (a wrong decode there) is left out if that fixes the fit. @p used gets the
 * distances the returned model was fitted on.
 */
sl_projector::DepthModel fitRationalLeavingOneOut(const PrimitiveFit& f, const std::vector<size_t>& seen_at,
                                                  const PlaneCalibrationOptions& options, std::vector<size_t>& used)
{
  std::vector<double> us, zs;
  for (size_t k : seen_at)
  {
    us.push_back(f.u[k]);
    zs.push_back(f.depth[k]);
  }
  sl_projector::DepthModel rat = fitRational(us, zs);
  used = seen_at;
  const bool inconsistent = !rat.valid || rat.rms > options.max_rational_rms;
  if (!inconsistent || f.distances <= options.min_distances)
    return rat;
  for (size_t drop = 0; drop < us.size(); ++drop)
  {
    std::vector<double> u2, z2;
    std::vector<size_t> i2;
    for (size_t i = 0; i < us.size(); ++i)
      if (i != drop)
      {
        u2.push_back(us[i]);
        z2.push_back(zs[i]);
        i2.push_back(seen_at[i]);
      }
    const sl_projector::DepthModel r2 = fitRational(u2, z2);
    if (r2.valid && (!rat.valid || r2.rms < rat.rms))
    {
      rat = r2;
      used = i2;
    }
  }
  return rat;
}

/// Both models of primitive @p f on the distances @p used (the rational one already fitted), and
/// their residuals there, also collected in @p residuals.
void fitModels(PrimitiveFit& f, const sl_projector::DepthModel& rational, const std::vector<size_t>& used,
               Residuals& residuals)
{
  std::vector<double> lu, lz;
  for (size_t k : used)
  {
    lu.push_back(f.u[k]);
    lz.push_back(f.depth[k]);
  }
  f.linear = fitLinear(lu, lz);
  f.rational = rational;
  for (size_t k : used)
  {
    f.linear_residual[k] = f.linear.depth(f.u[k]) - f.depth[k];
    f.rational_residual[k] = f.rational.depth(f.u[k]) - f.depth[k];
    residuals.linear[k].push_back(f.linear_residual[k]);
    residuals.rational[k].push_back(f.rational_residual[k]);
    residuals.all_linear.push_back(f.linear_residual[k]);
    residuals.all_rational.push_back(f.rational_residual[k]);
  }
}

/// The residual statistics of @p res: per distance and overall.
void summariseResiduals(const Residuals& residuals, PlaneCalibrationResult& res)
{
  for (size_t k = 0; k < res.distances.size(); ++k)
  {
    DistanceSummary& s = res.distances[k];
    s.calibrated = static_cast<int>(residuals.linear[k].size());
    s.linear_rms = rmsOf(residuals.linear[k]);
    s.rational_rms = rmsOf(residuals.rational[k]);
    for (double x : residuals.linear[k])
      s.linear_max = std::max(s.linear_max, std::abs(x));
    for (double x : residuals.rational[k])
      s.rational_max = std::max(s.rational_max, std::abs(x));
  }
  res.linear_rms = rmsOf(residuals.all_linear);
  res.rational_rms = rmsOf(residuals.all_rational);
}

/// Why no primitive of @p res could be calibrated.
std::string whyNoneCalibrated(const PlaneCalibrationResult& res, int min_distances)
{
  if (res.seen == 0)
    return "no primitive was decoded in any image";
  return std::to_string(res.too_few) + " of the " + std::to_string(res.seen) +
         " primitives seen were seen at fewer than " + std::to_string(min_distances) + " distances" +
         (res.rejected ? ", " + std::to_string(res.rejected) + " had inconsistent fits" : std::string());
}
}  // namespace

std::vector<size_t> PlaneCalibration::startResult(PlaneCalibrationResult& res) const
{
  std::vector<size_t> order(groups_.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return groups_[a].distance < groups_[b].distance; });
  for (size_t k : order)
  {
    DistanceSummary s;
    s.distance = groups_[k].distance;
    s.images = groups_[k].images;
    for (const auto& px : groups_[k].pixels)
      s.primitives += px.empty() ? 0 : 1;
    res.distances.push_back(s);
  }
  if (static_cast<int>(order.size()) < options_.min_distances)
    throw CalibrationError("plane calibration needs the plane at >= " + std::to_string(options_.min_distances) +
                           " different distances, got " + std::to_string(order.size()) + ": " +
                           listDistances(res.distances));
  const size_t cells = static_cast<size_t>(rig_.pattern.rows * rig_.pattern.cols);
  res.tables.distances.clear();
  for (const DistanceSummary& s : res.distances)
    res.tables.distances.push_back(s.distance);
  res.tables.linear.assign(cells, sl_projector::DepthModel());
  res.tables.rational.assign(cells, sl_projector::DepthModel());
  return order;
}

PrimitiveFit PlaneCalibration::observe(size_t cell, const std::vector<size_t>& order,
                                       std::vector<size_t>& seen_at) const
{
  const size_t nd = order.size();
  PrimitiveFit f;
  f.row = static_cast<int>(cell) / rig_.pattern.cols;
  f.col = static_cast<int>(cell) % rig_.pattern.cols;
  f.u.assign(nd, kNaN);
  f.v.assign(nd, kNaN);
  f.depth.assign(nd, kNaN);
  f.linear_residual.assign(nd, kNaN);
  f.rational_residual.assign(nd, kNaN);
  seen_at.clear();
  for (size_t k = 0; k < nd; ++k)
  {
    const Group& g = groups_[order[k]];
    const std::vector<Eigen::Vector2d>& px = g.pixels[cell];
    if (px.empty())
      continue;
    std::vector<double> u, v;
    for (const Eigen::Vector2d& q : px)
    {
      u.push_back(q.x());
      v.push_back(q.y());
    }
    const double mu = median(u), mv = median(v);
    const double z = depthOnPlane(rig_.camera, g.plane, mu, mv);
    if (!std::isfinite(z))
      continue;
    f.u[k] = mu;
    f.v[k] = mv;
    f.depth[k] = z;
    seen_at.push_back(k);
  }
  f.distances = static_cast<int>(seen_at.size());
  return f;
}

PlaneCalibrationResult PlaneCalibration::fit() const
{
  if (groups_.empty())
    throw CalibrationError("plane calibration: no images were added");
  PlaneCalibrationResult res;
  const std::vector<size_t> order = startResult(res);
  Residuals residuals(order.size());
  std::vector<size_t> seen_at, used;
  for (size_t cell = 0; cell < res.tables.rational.size(); ++cell)
  {
    PrimitiveFit f = observe(cell, order, seen_at);
    if (f.distances == 0)
      continue;
    ++res.seen;
    if (f.distances < options_.min_distances)
      ++res.too_few;
    else
    {
      const sl_projector::DepthModel rational = fitRationalLeavingOneOut(f, seen_at, options_, used);
      f.rejected = !rational.valid || rational.rms > options_.max_rational_rms;
      if (f.rejected)
        ++res.rejected;
      else
      {
        fitModels(f, rational, used, residuals);
        res.tables.linear[cell] = f.linear;
        res.tables.rational[cell] = f.rational;
        ++res.calibrated;
      }
    }
    res.primitives.push_back(std::move(f));
  }
  summariseResiduals(residuals, res);
  if (res.calibrated == 0)
    throw CalibrationError(
        "plane calibration: no primitive could be calibrated: " + whyNoneCalibrated(res, options_.min_distances) +
        ". Distances: " + listDistances(res.distances));
  return res;
}

std::string PlaneCalibrationResult::summary() const
{
  std::ostringstream o;
  o << "distance_m  images  primitives  calibrated  linear_rms_mm  linear_max_mm  rational_rms_mm  rational_max_mm\n";
  for (const DistanceSummary& s : distances)
  {
    char line[200];
    std::snprintf(line, sizeof(line), "%10.3f  %6d  %10d  %10d  %13.3f  %13.3f  %15.3f  %15.3f\n", s.distance, s.images,
                  s.primitives, s.calibrated, 1000.0 * s.linear_rms, 1000.0 * s.linear_max, 1000.0 * s.rational_rms,
                  1000.0 * s.rational_max);
    o << line;
  }
  o << "primitives: " << seen << " seen, " << calibrated << " calibrated, " << too_few << " seen at fewer than the "
    << "required distances, " << rejected << " rejected (inconsistent fit)\n";
  o << "residual rms over all calibrated primitives: linear " << mm(linear_rms, 3) << " mm, rational "
    << mm(rational_rms, 3) << " mm";
  if (distances.size() == 3)
    o << " (3 distances: the rational model is exact, its residual is 0 by construction)";
  o << "\n";
  if (too_few > 0)
  {
    o << "not calibrated (too few distances), row:col(distances):";
    int shown = 0;
    for (const PrimitiveFit& f : primitives)
      if (!f.rational.valid && !f.rejected)
      {
        if (shown++ == 40)
        {
          o << " ...";
          break;
        }
        o << " " << f.row << ":" << f.col << "(" << f.distances << ")";
      }
    o << "\n";
  }
  if (rejected > 0)
  {
    o << "rejected, row:col:";
    int shown = 0;
    for (const PrimitiveFit& f : primitives)
      if (f.rejected)
      {
        if (shown++ == 40)
        {
          o << " ...";
          break;
        }
        o << " " << f.row << ":" << f.col;
      }
    o << "\n";
  }
  return o.str();
}

std::string PlaneCalibrationResult::residualsCsv() const
{
  std::ostringstream o;
  o << "row,col,distances,status";
  for (const DistanceSummary& s : distances)
  {
    const std::string d = fixed(s.distance, 3);
    o << ",u_px@" << d << ",linear_mm@" << d << ",rational_mm@" << d;
  }
  o << "\n";
  auto num = [](double x, int digits) { return std::isfinite(x) ? fixed(x, digits) : std::string(); };
  for (const PrimitiveFit& f : primitives)
  {
    o << f.row << "," << f.col << "," << f.distances << ","
      << (f.rational.valid ? "calibrated"
          : f.rejected     ? "rejected"
                           : "too_few_distances");
    for (size_t k = 0; k < f.u.size(); ++k)
      o << "," << num(f.u[k], 3) << "," << num(1000.0 * f.linear_residual[k], 3) << ","
        << num(1000.0 * f.rational_residual[k], 3);
    o << "\n";
  }
  return o.str();
}

std::vector<ImageResidual> PlaneCalibrationResult::columnResiduals() const
{
  std::vector<ImageResidual> out;
  for (const PrimitiveFit& f : primitives)
  {
    if (!f.rational.valid)
      continue;
    const sl_projector::DepthModel& m = f.rational;
    for (size_t k = 0; k < f.u.size() && k < f.v.size(); ++k)
    {
      if (!std::isfinite(f.rational_residual[k]))
        continue;  // not seen there, or left out of the fit
      // The column where (a + b u) / (1 + c u) equals the plane's depth z.
      const double z = f.depth[k];
      const double u = (m.a - z) / (m.c * z - m.b);
      if (!std::isfinite(u))
        continue;
      ImageResidual r;
      r.pixel = Eigen::Vector2d(f.u[k], f.v[k]);
      r.residual = Eigen::Vector2d(u - f.u[k], 0.0);
      r.view = static_cast<int>(k);
      out.push_back(r);
    }
  }
  return out;
}

sl_projector::Rig withTables(const sl_projector::Rig& rig, const PlaneCalibrationResult& result)
{
  sl_projector::Rig out = rig;
  out.tables = result.tables;
  return out;
}

}  // namespace sl_calibration
