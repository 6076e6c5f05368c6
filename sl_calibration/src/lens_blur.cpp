#include "sl_calibration/lens_blur.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sl_calibration/common.h"

namespace sl_calibration
{

namespace
{
/// Bilinear sample of an 8-bit image; false outside it.
bool sample(const cv::Mat& grey, double x, double y, double& value)
{
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= grey.cols || y0 + 1 >= grey.rows)
    return false;
  const double ax = x - x0, ay = y - y0;
  const uchar* r0 = grey.ptr<uchar>(y0);
  const uchar* r1 = grey.ptr<uchar>(y0 + 1);
  value = (1 - ay) * ((1 - ax) * r0[x0] + ax * r0[x0 + 1]) + ay * ((1 - ax) * r1[x0] + ax * r1[x0 + 1]);
  return true;
}

constexpr double kStep = 0.5;  // profile sampling across the edge, px

/// The profile across the edge from @p a to @p b (image points), averaged over its middle 40 %;
/// empty if it leaves the image.
std::vector<double> edgeProfile(const cv::Mat& grey, const cv::Point2f& a, const cv::Point2f& b, double half_width)
{
  const double dx = b.x - a.x, dy = b.y - a.y, len = std::hypot(dx, dy);
  const double nx = -dy / len, ny = dx / len;
  const int n = static_cast<int>(std::floor(half_width / kStep)) * 2 + 1;
  std::vector<double> profile(static_cast<size_t>(n), 0.0);
  const double ts[] = { 0.3, 0.4, 0.5, 0.6, 0.7 };
  for (double t : ts)
    for (int i = 0; i < n; ++i)
    {
      const double s = (i - n / 2) * kStep;
      double v;
      if (!sample(grey, a.x + t * dx + s * nx, a.y + t * dy + s * ny, v))
        return {};
      profile[static_cast<size_t>(i)] += v / 5.0;
    }
  return profile;
}

/// Fits a + b Phi((s - s0) / sigma) to @p p (s0 from the gradient's centroid, sigma by a search,
/// a and b by least squares); false for no step. @p rms relative to |b|.
bool fitStep(const std::vector<double>& p, double& sigma, double& rms)
{
  const int n = static_cast<int>(p.size());
  double wsum = 0.0, wpos = 0.0;
  for (int i = 0; i + 1 < n; ++i)
  {
    const double g = std::abs(p[i + 1] - p[i]);
    wsum += g;
    wpos += g * (i + 0.5);
  }
  if (std::abs(p.back() - p.front()) < 20.0 || wsum <= 0.0)
    return false;  // no edge of useful contrast
  const double s0 = wpos / wsum;
  const double max_sigma = 0.4 * (n / 2) * kStep;
  double best = std::numeric_limits<double>::infinity(), best_b = 0.0;
  for (double s = 0.15; s <= max_sigma; s *= 1.02)
  {
    double S1 = 0, Sf = 0, Sff = 0, Sy = 0, Sfy = 0;
    std::vector<double> f(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
    {
      f[i] = 0.5 * std::erfc(-(i - s0) * kStep / (s * M_SQRT2));
      S1 += 1;
      Sf += f[i];
      Sff += f[i] * f[i];
      Sy += p[i];
      Sfy += f[i] * p[i];
    }
    const double det = S1 * Sff - Sf * Sf;
    if (std::abs(det) < 1e-12)
      continue;
    const double a = (Sy * Sff - Sf * Sfy) / det, b = (S1 * Sfy - Sf * Sy) / det;
    double r = 0.0;
    for (int i = 0; i < n; ++i)
      r += (a + b * f[i] - p[i]) * (a + b * f[i] - p[i]);
    if (r < best)
    {
      best = r;
      sigma = s;
      best_b = b;
    }
  }
  if (!std::isfinite(best) || std::abs(best_b) < 1e-9 || sigma >= max_sigma / 1.02)
    return false;
  rms = std::sqrt(best / n) / std::abs(best_b);
  return true;
}
}  // namespace

std::vector<EdgeBlur> measureBoardEdgeBlur(const cv::Mat& grey, const Board& board,
                                           const std::vector<cv::Point2f>& corners)
{
  std::vector<EdgeBlur> out;
  if (grey.type() != CV_8UC1 || static_cast<int>(corners.size()) != board.rows * board.cols)
    return out;
  const std::vector<cv::Point3f> object = board.objectPoints();
  auto edge = [&](int i, int j)
  {
    const cv::Point2f &a = corners[static_cast<size_t>(i)], &b = corners[static_cast<size_t>(j)];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len < 12.0)
      return;  // too small a square to see a whole edge profile
    // Half the square on either side, at most 12 px: the profile stays on the two squares.
    const std::vector<double> profile = edgeProfile(grey, a, b, std::min(12.0, 0.45 * len));
    EdgeBlur e;
    if (profile.empty() || !fitStep(profile, e.sigma, e.rms) || e.rms > 0.05)
      return;
    e.on_board = 0.5f * (object[static_cast<size_t>(i)] + object[static_cast<size_t>(j)]);
    out.push_back(e);
  };
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c < board.cols; ++c)
    {
      const int i = r * board.cols + c;
      if (c + 1 < board.cols)
        edge(i, i + 1);
      if (r + 1 < board.rows)
        edge(i, i + board.cols);
    }
  return out;
}

std::vector<BlurSample> blurAtDepth(const std::vector<EdgeBlur>& edges, const sl_projector::RigidTransform& board_pose)
{
  std::vector<BlurSample> out;
  out.reserve(edges.size());
  for (const EdgeBlur& e : edges)
  {
    const Eigen::Vector3d p = board_pose * Eigen::Vector3d(e.on_board.x, e.on_board.y, e.on_board.z);
    out.push_back(BlurSample{ p.z(), e.sigma });
  }
  return out;
}

namespace
{
/// sigma^2 = A + B x, x = (1/z - 1/zf)^2, A, B >= 0, by least squares in sigma^2; returns the
/// squared residual in sigma.
double fitAtFocus(const std::vector<BlurSample>& s, double zf, double& A, double& B)
{
  double n = 0, Sx = 0, Sy = 0, Sxx = 0, Sxy = 0;
  for (const BlurSample& b : s)
  {
    const double x = std::pow(1.0 / b.depth - 1.0 / zf, 2), y = b.sigma * b.sigma;
    n += 1;
    Sx += x;
    Sy += y;
    Sxx += x * x;
    Sxy += x * y;
  }
  const double det = n * Sxx - Sx * Sx;
  B = det > 1e-18 ? (n * Sxy - Sx * Sy) / det : 0.0;
  A = (Sy - B * Sx) / n;
  if (B < 0.0)
  {
    B = 0.0;
    A = Sy / n;
  }
  if (A < 0.0)
  {
    A = 0.0;
    B = Sxx > 0.0 ? Sxy / Sxx : 0.0;
  }
  double cost = 0.0;
  for (const BlurSample& b : s)
  {
    const double r = std::sqrt(A + B * std::pow(1.0 / b.depth - 1.0 / zf, 2)) - b.sigma;
    cost += r * r;
  }
  return cost;
}

/// The focus distance of least residual: a log grid over 0.15 to 5 m, then golden section.
double searchFocus(const std::vector<BlurSample>& s)
{
  double A, B, best = std::numeric_limits<double>::infinity(), best_zf = 0.675;
  const double lo = std::log(0.15), hi = std::log(5.0);
  const int steps = 400;
  for (int i = 0; i <= steps; ++i)
  {
    const double zf = std::exp(lo + (hi - lo) * i / steps);
    const double c = fitAtFocus(s, zf, A, B);
    if (c < best)
    {
      best = c;
      best_zf = zf;
    }
  }
  double a = std::log(best_zf) - (hi - lo) / steps, b = std::log(best_zf) + (hi - lo) / steps;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 40; ++it)
  {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if (fitAtFocus(s, std::exp(x1), A, B) < fitAtFocus(s, std::exp(x2), A, B))
      b = x2;
    else
      a = x1;
  }
  return std::exp(0.5 * (a + b));
}
}  // namespace

LensFit fitLensOptics(const std::vector<BlurSample>& samples_in, double f_px, double pixel_pitch)
{
  LensFit fit;
  fit.lens.pixel_pitch = pixel_pitch;
  std::vector<BlurSample> s;
  for (const BlurSample& b : samples_in)
    if (std::isfinite(b.depth) && b.depth > 0.0 && std::isfinite(b.sigma) && b.sigma > 0.0)
      s.push_back(b);
  if (s.size() < 10)
  {
    fit.samples = static_cast<int>(s.size());
    fit.note = s.empty() ? "no board edge measured (board images give them)"
                         : std::to_string(s.size()) + " blur samples (need 10)";
    return fit;
  }
  double A = 0.0, B = 0.0;
  double zf = searchFocus(s);
  double cost = fitAtFocus(s, zf, A, B);
  // Once more without the samples far off the fit (an edge blurred by a nearby corner, noise).
  const double cut = 3.0 * std::max(std::sqrt(cost / s.size()), 0.02);
  std::vector<BlurSample> kept;
  for (const BlurSample& b : s)
    if (std::abs(std::sqrt(A + B * std::pow(1.0 / b.depth - 1.0 / zf, 2)) - b.sigma) <= cut)
      kept.push_back(b);
  if (kept.size() >= 10 && kept.size() < s.size())
  {
    s = kept;
    zf = searchFocus(s);
    cost = fitAtFocus(s, zf, A, B);
  }
  fit.samples = static_cast<int>(s.size());
  fit.rms = std::sqrt(cost / s.size());
  fit.base_sigma = std::sqrt(A);
  fit.min_depth = fit.max_depth = s.front().depth;
  int nearer = 0, farther = 0;
  for (const BlurSample& b : s)
  {
    fit.min_depth = std::min(fit.min_depth, b.depth);
    fit.max_depth = std::max(fit.max_depth, b.depth);
    nearer += b.depth < 0.95 * zf;
    farther += b.depth > 1.05 * zf;
  }
  // k = (D / 4) / |1/z - 1/zf| = (f / N) f_px zf / (zf - f) / 4, f = f_px * pitch.
  const double f = f_px * pixel_pitch, k = std::sqrt(B);
  fit.lens.focus_distance = zf;
  fit.lens.f_number = k > 0.0 && zf > f ? f * f_px * zf / ((zf - f) * 4.0 * k) : 0.0;
  const int need = std::max(5, fit.samples / 10);
  if (!(fit.lens.f_number > 0.5 && fit.lens.f_number < 64.0))
    fit.note = "no defocus blur measured (the blur does not change with depth)";
  else if (nearer < need || farther < need)
    fit.note = "the samples (" + fixed(fit.min_depth, 2) + " to " + fixed(fit.max_depth, 2) +
               " m) do not lie on both sides of the focus (fitted " + fixed(zf, 2) + " m; " + std::to_string(nearer) +
               " nearer, " + std::to_string(farther) + " farther, " + std::to_string(need) +
               " each needed): add board views nearer and farther";
  else if (fit.rms > 0.25)
    fit.note = "the blur does not follow a thin lens (residual " + fixed(fit.rms, 2) + " px rms)";
  fit.valid = fit.note.empty();
  return fit;
}

std::string LensFit::summary(const std::string& what) const
{
  if (!valid)
    return what + " lens optics not estimated: " + note + "\n";
  return what + " lens optics from " + std::to_string(samples) + " board edges at " + fixed(min_depth, 2) + " to " +
         fixed(max_depth, 2) + " m: focus " + fixed(lens.focus_distance, 3) + " m, f/" + fixed(lens.f_number, 2) +
         " (pixel pitch " + fixed(lens.pixel_pitch * 1e6, 2) + " um), blur at focus " + fixed(base_sigma, 2) +
         " px, residual " + fixed(rms, 3) + " px rms\n";
}

}  // namespace sl_calibration
