#include "sl_evaluation/plot.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace sl_evaluation
{

namespace
{
// Margins around the plot areas, px: tick labels and the y label left, legends right, the title on
// top, x tick labels and the x label below, tick labels between panels.
constexpr int kLeft = 80;
constexpr int kRight = 200;
constexpr int kTop = 50;
constexpr int kBottom = 60;
constexpr int kGap = 45;
constexpr int kMinWidth = 400;
constexpr int kMinPanelHeight = 60;
constexpr int kMarkerRadius = 4;
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kGrid(225, 225, 225);
const cv::Scalar kWhite(255, 255, 255);

void validateAxis(const ChartAxis& a, const std::string& name)
{
  if (!std::isfinite(a.min))
    throw std::invalid_argument(name + ".min: must be finite");
  if (!std::isfinite(a.max) || !(a.max > a.min))
    throw std::invalid_argument(name + ".max: must be finite and above " + name + ".min");
  if (!std::isfinite(a.tick) || a.tick < 0.0)
    throw std::invalid_argument(name + ".tick: must be 0 (automatic) or positive");
  if (a.tick > 0.0 && (a.max - a.min) / a.tick > 100.0)
    throw std::invalid_argument(name + ".tick: gives more than 100 ticks");
}

double tickOf(const ChartAxis& a)
{
  return a.tick > 0.0 ? a.tick : niceTick(a.min, a.max);
}

/// Tick values of an axis: the multiples of its tick within [min, max].
std::vector<double> ticks(const ChartAxis& a)
{
  const double t = tickOf(a);
  std::vector<double> out;
  for (double k = std::ceil(a.min / t - 1e-9); k * t <= a.max + 1e-9 * t; k += 1.0)
    out.push_back(std::abs(k) < 0.5 ? 0.0 : k * t);
  return out;
}

/// A tick label with as many decimals as the tick spacing needs.
std::string tickLabel(double value, double tick)
{
  int decimals = 0;
  for (double scaled = tick; decimals < 6 && std::abs(scaled - std::round(scaled)) > 1e-6 * scaled; scaled *= 10.0)
    ++decimals;
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, value);
  return buf;
}

cv::Size textSize(const std::string& text, double scale)
{
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline);
}

/// Text with its left end at x and its vertical middle at y.
void text(cv::Mat& image, const std::string& s, int x, int y, double scale)
{
  cv::putText(image, s, cv::Point(x, y + textSize(s, scale).height / 2), kFont, scale, kInk, 1, cv::LINE_AA);
}

/// Text turned 90 degrees counter-clockwise, centred on (cx, cy), cut at the image border.
void verticalText(cv::Mat& image, const std::string& s, int cx, int cy, double scale)
{
  const cv::Size size = textSize(s, scale);
  cv::Mat patch(size.height + 8, size.width + 4, CV_8UC3, kWhite);
  cv::putText(patch, s, cv::Point(2, size.height + 2), kFont, scale, kInk, 1, cv::LINE_AA);
  cv::rotate(patch, patch, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect where(cx - patch.cols / 2, cy - patch.rows / 2, patch.cols, patch.rows);
  const cv::Rect inside = where & cv::Rect(0, 0, image.cols, image.rows);
  patch(cv::Rect(inside.x - where.x, inside.y - where.y, inside.width, inside.height)).copyTo(image(inside));
}

int panelHeight(const Chart& chart)
{
  const int n = static_cast<int>(chart.panels.size());
  return (chart.height - kTop - kBottom - kGap * (n - 1)) / n;
}

/// Pixel coordinate of v on an axis from lo (at p0) to hi (at p1), kept far from int overflow.
int toPixel(double v, double lo, double hi, int p0, int p1)
{
  const double p = p0 + (v - lo) / (hi - lo) * (p1 - p0);
  return static_cast<int>(std::lround(std::clamp(p, -1e6, 1e6)));
}

void drawAxes(cv::Mat& image, const Chart& chart, size_t i, bool bottom)
{
  const cv::Rect r = chartPlotArea(chart, i);
  const ChartAxis& y = chart.panels[i].y;
  const double xt = tickOf(chart.x), yt = tickOf(y);
  for (double v : ticks(chart.x))
  {
    const int px = chartPixel(chart, i, v, y.min).x;
    cv::line(image, { px, r.y }, { px, r.y + r.height - 1 }, kGrid);
    cv::line(image, { px, r.y + r.height - 1 }, { px, r.y + r.height + 3 }, kInk);
    const std::string label = tickLabel(v, xt);
    text(image, label, px - textSize(label, 0.45).width / 2, r.y + r.height + 16, 0.45);
  }
  for (double v : ticks(y))
  {
    const int py = chartPixel(chart, i, chart.x.min, v).y;
    cv::line(image, { r.x, py }, { r.x + r.width - 1, py }, kGrid);
    cv::line(image, { r.x - 4, py }, { r.x, py }, kInk);
    const std::string label = tickLabel(v, yt);
    text(image, label, r.x - 7 - textSize(label, 0.45).width, py, 0.45);
  }
  cv::rectangle(image, r, kInk);
  verticalText(image, y.label, 18, r.y + r.height / 2, 0.5);
  if (bottom)
    text(image, chart.x.label, r.x + (r.width - textSize(chart.x.label, 0.5).width) / 2, r.y + r.height + 40, 0.5);
}

bool finite(const cv::Point2d& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y);
}

/// Lines of every series first, then the markers, so that no line covers a point.
void drawSeries(cv::Mat& image, const Chart& chart, size_t i)
{
  const cv::Rect r = chartPlotArea(chart, i);
  const ChartPanel& panel = chart.panels[i];
  bool any = false;
  for (const ChartSeries& s : panel.series)
    for (size_t k = 0; k + 1 < s.points.size(); ++k)
    {
      if (!finite(s.points[k]) || !finite(s.points[k + 1]))
        continue;
      cv::Point a = chartPixel(chart, i, s.points[k].x, s.points[k].y);
      cv::Point b = chartPixel(chart, i, s.points[k + 1].x, s.points[k + 1].y);
      // Inside the frame by 1 px: the 2 px line's caps stay in the plot area.
      if (cv::clipLine(cv::Rect(r.x + 1, r.y + 1, r.width - 2, r.height - 2), a, b))
        cv::line(image, a, b, s.colour, 2, cv::LINE_AA);
    }
  for (const ChartSeries& s : panel.series)
    for (const cv::Point2d& p : s.points)
    {
      const cv::Point q = finite(p) ? chartPixel(chart, i, p.x, p.y) : cv::Point(-1, -1);
      if (finite(p) && r.contains(q))
      {
        cv::circle(image, q, kMarkerRadius, s.colour, cv::FILLED, cv::LINE_8);
        any = true;
      }
    }
  if (!any)
    text(image, "no data", r.x + (r.width - textSize("no data", 0.6).width) / 2, r.y + r.height / 2, 0.6);
}

void drawLegend(cv::Mat& image, const Chart& chart, size_t i)
{
  const cv::Rect r = chartPlotArea(chart, i);
  const int x0 = r.x + r.width + 15;
  int y = r.y + 10;
  for (const ChartSeries& s : chart.panels[i].series)
  {
    cv::line(image, { x0, y }, { x0 + 30, y }, s.colour, 2, cv::LINE_AA);
    cv::circle(image, { x0 + 15, y }, kMarkerRadius, s.colour, cv::FILLED, cv::LINE_8);
    text(image, s.label, x0 + 38, y, 0.5);
    y += 22;
  }
}
}  // namespace

void Chart::validate() const
{
  if (width < kMinWidth)
    throw std::invalid_argument("width: must be at least " + std::to_string(kMinWidth) + " px");
  if (panels.empty())
    throw std::invalid_argument("panels: a chart needs at least one panel");
  if (height < kTop + kBottom + kMinPanelHeight || panelHeight(*this) < kMinPanelHeight)
    throw std::invalid_argument("height: too small for " + std::to_string(panels.size()) + " panels of at least " +
                                std::to_string(kMinPanelHeight) + " px");
  validateAxis(x, "x");
  for (size_t i = 0; i < panels.size(); ++i)
    validateAxis(panels[i].y, "panels[" + std::to_string(i) + "].y");
}

double niceTick(double lo, double hi)
{
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo))
    throw std::invalid_argument("niceTick: needs finite lo < hi");
  const double raw = (hi - lo) / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / magnitude;
  return magnitude * (n < 1.5 ? 1.0 : n < 3.5 ? 2.0 : n < 7.5 ? 5.0 : 10.0);
}

ChartAxis fitAxis(const std::string& label, const std::vector<double>& values, bool from_zero)
{
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values)
    if (std::isfinite(v))
    {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  ChartAxis a;
  a.label = label;
  if (!std::isfinite(lo))
    return a;  // [0, 1]: nothing to hold
  if (from_zero)
  {
    lo = std::min(lo, 0.0);
    hi = std::max(hi, 0.0);
  }
  if (!(hi > lo))
  {
    const double pad = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
    hi += pad;
    if (!from_zero || lo != 0.0)
      lo -= pad;
  }
  const double t = niceTick(lo, hi);
  a.min = std::floor(lo / t + 1e-9) * t;
  a.max = std::ceil(hi / t - 1e-9) * t;
  a.tick = t;
  return a;
}

cv::Rect chartPlotArea(const Chart& chart, size_t panel)
{
  chart.validate();
  if (panel >= chart.panels.size())
    throw std::invalid_argument("panel " + std::to_string(panel) + ": the chart has " +
                                std::to_string(chart.panels.size()) + " panels");
  const int h = panelHeight(chart);
  return cv::Rect(kLeft, kTop + static_cast<int>(panel) * (h + kGap), chart.width - kLeft - kRight, h);
}

cv::Point chartPixel(const Chart& chart, size_t panel, double x, double y)
{
  const cv::Rect r = chartPlotArea(chart, panel);
  const ChartAxis& ya = chart.panels[panel].y;
  return cv::Point(toPixel(x, chart.x.min, chart.x.max, r.x, r.x + r.width - 1),
                   toPixel(y, ya.min, ya.max, r.y + r.height - 1, r.y));
}

cv::Mat renderChart(const Chart& chart)
{
  chart.validate();
  cv::Mat image(chart.height, chart.width, CV_8UC3, kWhite);
  text(image, chart.title, std::max(5, (chart.width - textSize(chart.title, 0.6).width) / 2), kTop / 2, 0.6);
  for (size_t i = 0; i < chart.panels.size(); ++i)
  {
    drawAxes(image, chart, i, i + 1 == chart.panels.size());
    drawSeries(image, chart, i);
    drawLegend(image, chart, i);
  }
  return image;
}

void checkChartPath(const std::string& path)
{
  std::string suffix = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  std::transform(suffix.begin(), suffix.end(), suffix.begin(), [](unsigned char c) { return std::tolower(c); });
  if (suffix != ".png")
    throw std::invalid_argument("the chart's file name must end in .png, got '" + path + "'");
  struct stat st;
  if (stat(path.c_str(), &st) == 0)
  {
    if (S_ISDIR(st.st_mode))
      throw std::runtime_error("cannot write " + path + ": it is a directory");
    if (access(path.c_str(), W_OK) != 0)
      throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
    return;
  }
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw std::runtime_error("cannot write " + path + ": no directory " + dir);
  if (access(dir.c_str(), W_OK | X_OK) != 0)
    throw std::runtime_error("cannot write " + path + ": directory " + dir + ": " + std::strerror(errno));
}

void writeChart(const Chart& chart, const std::string& path)
{
  const cv::Mat image = renderChart(chart);
  checkChartPath(path);
  bool written = false;
  try
  {
    written = cv::imwrite(path, image, { cv::IMWRITE_PNG_COMPRESSION, 9 });
  }
  catch (const cv::Exception& e)
  {
    throw std::runtime_error("cannot write " + path + ": " + e.what());
  }
  if (!written)
    throw std::runtime_error("cannot write " + path);
}

Chart decodingChart(std::vector<DistanceResult> results, const std::string& title)
{
  std::stable_sort(results.begin(), results.end(),
                   [](const DistanceResult& a, const DistanceResult& b) { return a.distance < b.distance; });
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ChartSeries valid{ "valid % of visible", {}, cv::Scalar(180, 90, 20) };
  ChartSeries mean{ "mean", {}, cv::Scalar(50, 150, 30) };
  ChartSeries p95{ "95th percentile", {}, cv::Scalar(0, 140, 255) };
  ChartSeries max{ "max", {}, cv::Scalar(40, 40, 210) };
  std::vector<double> distances, errors;
  for (const DistanceResult& r : results)
  {
    const EvalStats& s = r.stats;
    const double d = r.distance;
    distances.push_back(d);
    valid.points.emplace_back(d, s.visible > 0 ? s.validPercent() : nan);
    const bool depth = s.with_depth > 0;
    mean.points.emplace_back(d, depth ? s.meanErrorMm() : nan);
    p95.points.emplace_back(d, depth ? s.errorPercentileMm(95.0) : nan);
    max.points.emplace_back(d, depth ? s.maxErrorMm() : nan);
    for (const ChartSeries* e : { &mean, &p95, &max })
      errors.push_back(e->points.back().y);
  }
  Chart chart;
  chart.title = title;
  chart.x = fitAxis("distance from the camera (m)", distances, false);
  chart.panels.resize(2);
  chart.panels[0].y = ChartAxis{ "valid (%)", 0.0, 100.0, 20.0 };
  chart.panels[0].series = { valid };
  chart.panels[1].y = fitAxis("|depth error| (mm)", errors, true);
  chart.panels[1].series = { mean, p95, max };
  return chart;
}

}  // namespace sl_evaluation
