#include "sl_calibration/residual_plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace sl_calibration
{
namespace
{
constexpr int kMargin = 20;            // left and right of the image area, px
constexpr int kLine = 22;              // height of a text line, px
constexpr int kShift = 4;              // sub-pixel bits of the drawing calls
constexpr double kArrowTarget = 30.0;  // automatic magnification: the 95th percentile drawn this long, px
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTitleFont = 0.55, kTextFont = 0.45;
const cv::Scalar kText(0, 0, 0), kBackground(255, 255, 255), kImageArea(248, 248, 248), kBorder(150, 150, 150);

/// The largest 1, 2 or 5 times a power of ten that is at most @p x (> 0).
double niceFloor(double x)
{
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  const double m = x / p;
  return (m >= 5.0 ? 5.0 : m >= 2.0 ? 2.0 : 1.0) * p;
}

/// @p x with up to 3 significant digits ("0.05", "100", "2.5").
std::string compact(double x)
{
  std::ostringstream o;
  o << std::setprecision(3) << x;
  return o.str();
}

/// The lines of @p text ('\n'), each broken between words to fit @p width px in the title font.
std::vector<std::string> titleLines(const std::string& text, int width)
{
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string paragraph; std::getline(in, paragraph);)
  {
    std::istringstream words(paragraph);
    std::string line;
    for (std::string w; words >> w;)
    {
      const std::string longer = line.empty() ? w : line + " " + w;
      int base = 0;
      if (!line.empty() && cv::getTextSize(longer, kFont, kTitleFont, 1, &base).width > width)
      {
        out.push_back(line);
        line = w;
      }
      else
        line = longer;
    }
    out.push_back(line);
  }
  return out;
}

/// Colour of view @p v: ten distinct colours (BGR), repeated.
cv::Scalar viewColour(int v)
{
  static const cv::Scalar palette[] = { { 180, 119, 31 },  { 14, 127, 255 }, { 44, 160, 44 },   { 40, 39, 214 },
                                        { 189, 103, 148 }, { 75, 86, 140 },  { 194, 119, 227 }, { 127, 127, 127 },
                                        { 34, 189, 188 },  { 207, 190, 23 } };
  return palette[((v % 10) + 10) % 10];
}

/// Colour of a residual @p t of the largest (0..1): blue, green, red.
cv::Scalar magnitudeColour(double t)
{
  t = std::min(1.0, std::max(0.0, t));
  if (t < 0.5)
    return cv::Scalar(255.0 * (1.0 - 2.0 * t), 170.0 * 2.0 * t, 0.0);
  return cv::Scalar(0.0, 170.0 * (2.0 - 2.0 * t), 255.0 * (2.0 * t - 1.0));
}

cv::Point fixedPoint(const cv::Point2d& p)
{
  return cv::Point(static_cast<int>(std::lround(p.x * (1 << kShift))),
                   static_cast<int>(std::lround(p.y * (1 << kShift))));
}

std::vector<double> finiteLengths(const std::vector<ImageResidual>& residuals)
{
  std::vector<double> out;
  for (const ImageResidual& r : residuals)
    if (r.pixel.allFinite() && r.residual.allFinite())
      out.push_back(r.residual.norm());
  return out;
}

/// The magnification: the given one, or a 1-2-5 step drawing the 95th percentile about 30 px long.
double chooseMagnification(std::vector<double> lengths, double given, double scale)
{
  if (given > 0.0)
    return given;
  std::sort(lengths.begin(), lengths.end());
  const double p95 = lengths[std::min(lengths.size() - 1, static_cast<size_t>(0.95 * lengths.size()))];
  const double typical = p95 > 0.0 ? p95 : lengths.back();
  if (!(typical > 0.0))
    return 1.0;
  return std::min(1e6, std::max(1e-3, niceFloor(kArrowTarget / (typical * scale))));
}

/// A legend entry of a view: its colour box and name.
struct LegendEntry
{
  std::string text;
  cv::Scalar colour;
  int width;
};

std::vector<LegendEntry> viewLegend(const std::vector<ImageResidual>& residuals, const ResidualPlotOptions& options)
{
  int views = 0;
  for (const ImageResidual& r : residuals)
    views = std::max(views, r.view + 1);
  std::vector<LegendEntry> out;
  for (int v = 0; v < views; ++v)
  {
    const std::string text =
        static_cast<size_t>(v) < options.view_names.size() ? options.view_names[v] : "view " + std::to_string(v + 1);
    int base = 0;
    const int w = cv::getTextSize(text, kFont, kTextFont, 1, &base).width;
    out.push_back(LegendEntry{ text, viewColour(v), 12 + 6 + w + 18 });
  }
  return out;
}

/// Rows the legend entries take in a strip @p width px wide.
int legendRows(const std::vector<LegendEntry>& entries, int width)
{
  int rows = entries.empty() ? 0 : 1, x = 0;
  for (const LegendEntry& e : entries)
  {
    if (x > 0 && x + e.width > width)
    {
      ++rows;
      x = 0;
    }
    x += e.width;
  }
  return rows;
}

void putText(cv::Mat& img, const std::string& text, int x, int y, double font = kTextFont)
{
  cv::putText(img, text, cv::Point(x, y), kFont, font, kText, 1, cv::LINE_AA);
}

/// The scale bar and the magnification, at the left of row @p y.
void drawScaleBar(cv::Mat& img, const ResidualPlotLayout& l, int y)
{
  const int x0 = kMargin, x1 = kMargin + l.scale_bar_length;
  cv::line(img, cv::Point(x0, y), cv::Point(x1, y), kText, 2);
  cv::line(img, cv::Point(x0, y - 5), cv::Point(x0, y + 5), kText, 1);
  cv::line(img, cv::Point(x1, y - 5), cv::Point(x1, y + 5), kText, 1);
  putText(img,
          compact(l.scale_bar_residual) + " px residual;  residuals x" + compact(l.magnification) +
              " (arrow: from the observed to the predicted position)",
          x1 + 10, y + 5);
}

/// The colour legend from row @p y on.
void drawLegend(cv::Mat& img, const std::vector<LegendEntry>& entries, const ResidualStatistics& stats,
                ResidualColouring colouring, int y)
{
  if (colouring == ResidualColouring::ByMagnitude)
  {
    const int w = 150;
    for (int i = 0; i < w; ++i)
      cv::line(img, cv::Point(kMargin + i, y - 6), cv::Point(kMargin + i, y + 6),
               magnitudeColour(static_cast<double>(i) / (w - 1)), 1);
    putText(img, "0", kMargin - 12, y + 5);
    putText(img, compact(stats.max) + " px", kMargin + w + 6, y + 5);
    return;
  }
  int x = kMargin;
  for (const LegendEntry& e : entries)
  {
    if (x > kMargin && x + e.width > img.cols - kMargin)
    {
      x = kMargin;
      y += kLine - 2;
    }
    cv::rectangle(img, cv::Rect(x, y - 6, 12, 12), e.colour, cv::FILLED);
    putText(img, e.text, x + 18, y + 5);
    x += e.width;
  }
}

/// The image area with every residual; arrows that leave it are cut at its border.
void drawResiduals(cv::Mat& img, const std::vector<ImageResidual>& residuals, const ResidualPlotLayout& l,
                   const ResidualPlotOptions& options, double max_length)
{
  cv::Mat area = img(l.image_area);  // drawing on the view clips to it
  area.setTo(kImageArea);
  const cv::Point2d origin(l.image_area.x, l.image_area.y);
  for (const ImageResidual& r : residuals)
  {
    if (!r.pixel.allFinite() || !r.residual.allFinite())
      continue;
    const cv::Scalar colour = options.colouring == ResidualColouring::ByView
                                  ? viewColour(r.view)
                                  : magnitudeColour(max_length > 0.0 ? r.residual.norm() / max_length : 0.0);
    const cv::Point2d p0 = l.toPicture(r.pixel) - origin;
    const cv::Point2d d(r.residual.x() * l.magnification * l.scale, r.residual.y() * l.magnification * l.scale);
    const cv::Point2d p1 = p0 + d;
    const double len = std::hypot(d.x, d.y);
    // Plain lines (no anti-aliasing): a few colours keep the PNG small.
    if (len >= 6.0)
      cv::arrowedLine(area, fixedPoint(p0), fixedPoint(p1), colour, 1, cv::LINE_8, kShift, std::min(0.35, 5.0 / len));
    else if (len > 0.0)
      cv::line(area, fixedPoint(p0), fixedPoint(p1), colour, 1, cv::LINE_8, kShift);
    cv::circle(area, fixedPoint(p0), 1 << kShift, colour, cv::FILLED, cv::LINE_8, kShift);
  }
  cv::rectangle(img, l.image_area, kBorder, 1);
}
}  // namespace

void ResidualPlotOptions::validate() const
{
  if (image_size.width <= 0 || image_size.height <= 0)
    throw std::invalid_argument("image_size: must be positive, got " + std::to_string(image_size.width) + " x " +
                                std::to_string(image_size.height));
  if (width < 200 || width > 10000)
    throw std::invalid_argument("width: must be in [200, 10000] px, got " + std::to_string(width));
  if (!(magnification >= 0.0 && std::isfinite(magnification)))
    throw std::invalid_argument("magnification: must be >= 0 (0: automatic), got " + std::to_string(magnification));
}

cv::Point2d ResidualPlotLayout::toPicture(const Eigen::Vector2d& pixel) const
{
  return cv::Point2d(image_area.x + scale * (pixel.x() + 0.5), image_area.y + scale * (pixel.y() + 0.5));
}

ResidualStatistics residualStatistics(const std::vector<ImageResidual>& residuals)
{
  ResidualStatistics s;
  double sum2 = 0.0;
  for (double len : finiteLengths(residuals))
  {
    ++s.points;
    sum2 += len * len;
    s.max = std::max(s.max, len);
  }
  s.rms = s.points ? std::sqrt(sum2 / s.points) : 0.0;
  return s;
}

cv::Mat drawResidualPlot(const std::vector<ImageResidual>& residuals, const ResidualPlotOptions& options,
                         ResidualPlotLayout* layout)
{
  options.validate();
  const std::vector<double> lengths = finiteLengths(residuals);
  if (lengths.empty())
    throw CalibrationError("no residuals to plot");
  const ResidualStatistics stats = residualStatistics(residuals);
  const std::vector<std::string> title = titleLines(options.title, options.width - 2 * kMargin);
  const std::vector<LegendEntry> legend =
      options.colouring == ResidualColouring::ByView ? viewLegend(residuals, options) : std::vector<LegendEntry>();

  ResidualPlotLayout l;
  l.scale = static_cast<double>(options.width - 2 * kMargin) / options.image_size.width;
  const int top = 8 + kLine * static_cast<int>(title.size() + 1) + 6;
  l.image_area = cv::Rect(kMargin, top, options.width - 2 * kMargin,
                          static_cast<int>(std::lround(options.image_size.height * l.scale)));
  const int rows = options.colouring == ResidualColouring::ByView ? legendRows(legend, options.width - 2 * kMargin) : 1;
  l.size = cv::Size(options.width, l.image_area.br().y + 14 + kLine + rows * (kLine - 2) + 6);
  l.magnification = chooseMagnification(lengths, options.magnification, l.scale);
  l.scale_bar_residual = niceFloor(80.0 / (l.magnification * l.scale));
  l.scale_bar_length = static_cast<int>(std::lround(l.scale_bar_residual * l.magnification * l.scale));

  cv::Mat img(l.size, CV_8UC3, kBackground);
  int y = 8 + kLine - 6;
  for (const std::string& t : title)
  {
    putText(img, t, kMargin, y, kTitleFont);
    y += kLine;
  }
  putText(img,
          "RMS " + fixed(stats.rms, 3) + " px, max " + fixed(stats.max, 3) + " px, " + std::to_string(stats.points) +
              " points; camera image " + std::to_string(options.image_size.width) + " x " +
              std::to_string(options.image_size.height) + " px",
          kMargin, y);
  drawResiduals(img, residuals, l, options, stats.max);
  const int bar_y = l.image_area.br().y + 14 + kLine / 2;
  drawScaleBar(img, l, bar_y);
  drawLegend(img, legend, stats, options.colouring, bar_y + kLine);
  if (layout)
    *layout = l;
  return img;
}

bool isPngPath(const std::string& path)
{
  if (path.size() < 4)
    return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png";
}

void writeResidualPlot(const std::string& path, const std::vector<ImageResidual>& residuals,
                       const ResidualPlotOptions& options)
{
  if (!isPngPath(path))
    throw CalibrationError(path + ": a residual plot is written as PNG, the file name must end in .png");
  cv::Mat img;
  try
  {
    img = drawResidualPlot(residuals, options);
  }
  catch (const std::exception& e)
  {
    throw CalibrationError(path + ": " + e.what());
  }
  bool ok = false;
  std::string why;
  try
  {
    ok = cv::imwrite(path, img, { cv::IMWRITE_PNG_COMPRESSION, 9 });
  }
  catch (const cv::Exception& e)
  {
    why = std::string(": ") + e.what();
  }
  if (!ok)
    throw CalibrationError(path + ": cannot write the residual plot (does the folder exist and may it be written?)" +
                           why);
}

void writePlaneResidualPlot(const std::string& path, const PlaneCalibrationResult& result, cv::Size image_size)
{
  ResidualPlotOptions o;
  o.image_size = image_size;
  o.title = "sl_calibrate_plane: rational depth model, image column residuals (depth rms " +
            fixed(1000.0 * result.rational_rms, 3) + " mm)\nper primitive and distance: the column where its model " +
            "puts the plane minus the column where it was seen";
  for (const DistanceSummary& d : result.distances)
    o.view_names.push_back(fixed(d.distance, 3) + " m");
  writeResidualPlot(path, result.columnResiduals(), o);
}

namespace
{
/// A short legend name of a board view: the board image's file name (a plane view is named
/// "BOARD + PATTERN").
std::string shortViewName(const std::string& name)
{
  std::string s = name.substr(0, name.find(" + "));
  const size_t slash = s.find_last_of('/');
  if (slash != std::string::npos)
    s = s.substr(slash + 1);
  return s.size() > 28 ? s.substr(0, 25) + "..." : s;
}
}  // namespace

void writeCameraResidualPlot(const std::string& path, const FullCalibrationResult& result)
{
  if (result.camera_residuals.empty())
    throw CalibrationError(path +
                           ": no board corners to plot (no board views: the camera model was given and "
                           "every plane view is at a known distance)");
  ResidualPlotOptions o;
  o.image_size = cv::Size(result.rig.camera.width, result.rig.camera.height);
  o.title = std::string("sl_calibrate_full: camera reprojection residuals of the board corners (") +
            (result.camera_calibrated ? "calibrated" : "given") + " camera, " +
            std::to_string(result.camera_views.size()) + " board views" +
            (result.refined ? ", after the joint refinement)" : ")");
  for (const std::string& v : result.camera_views)
    o.view_names.push_back(shortViewName(v));
  writeResidualPlot(path, result.camera_residuals, o);
}

}  // namespace sl_calibration
