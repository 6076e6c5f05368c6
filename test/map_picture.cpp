#include "map_picture.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace sl_bringup_test
{
namespace
{
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kFontScale = 0.5;
constexpr int kLine = 18;    // pixels per text line
constexpr int kBottom = 44;  // pixels below the map: scale bar and legend
const char* const kLegend = "path blue to red, start o, end x; scene outline orange";
const cv::Scalar kUnknown(185, 185, 185);
const cv::Scalar kOutline(0, 140, 255);  // BGR orange

/// Index of the cell whose lower left corner is at @p v (a multiple of @p resolution).
long cornerIndex(double v, double resolution, const char* what)
{
  const double i = v / resolution;
  if (!std::isfinite(i) || std::abs(i - std::round(i)) > 1e-3)
    throw std::invalid_argument(std::string("occupancy grid: ") + what + " " + std::to_string(v) +
                                " m is not on the cells of resolution " + std::to_string(resolution) + " m");
  return std::lround(i);
}

/// Grey of a known cell: 0 (free) light .. 100 (occupied) dark.
cv::Vec3b shadeOf(std::int8_t v)
{
  if (v < 0)
    return cv::Vec3b(kUnknown[0], kUnknown[1], kUnknown[2]);
  const auto g = static_cast<unsigned char>(245 - 2 * std::min<int>(v, 100));
  return cv::Vec3b(g, g, g);
}
}  // namespace

void MapBox::add(const MapPoint& p)
{
  if (empty())
  {
    min_x = max_x = p.x;
    min_y = max_y = p.y;
    return;
  }
  min_x = std::min(min_x, p.x);
  max_x = std::max(max_x, p.x);
  min_y = std::min(min_y, p.y);
  max_y = std::max(max_y, p.y);
}

MapPoint MapFrame::fromWorld(double world_x, double world_y) const
{
  const double dx = world_x - x, dy = world_y - y, c = std::cos(yaw), s = std::sin(yaw);
  return { c * dx + s * dy, -s * dx + c * dy };
}

MapPoint MapFrame::toWorld(const MapPoint& p) const
{
  const double c = std::cos(yaw), s = std::sin(yaw);
  return { x + c * p.x - s * p.y, y + s * p.x + c * p.y };
}

std::vector<MapPoint> sceneOutline(const sl_sim::Scene& scene, const MapFrame& frame, const MapBox& box,
                                   const std::vector<double>& heights, double step)
{
  std::vector<MapPoint> points;
  if (box.empty() || !(step > 0.0))
    return points;
  for (const bool along_y : { false, true })
  {
    const double length = along_y ? box.max_y - box.min_y : box.max_x - box.min_x;
    const double a = frame.yaw + (along_y ? M_PI / 2.0 : 0.0);
    for (double across = along_y ? box.min_x : box.min_y; across <= (along_y ? box.max_x : box.max_y); across += step)
    {
      const MapPoint from = along_y ? MapPoint{ across, box.min_y } : MapPoint{ box.min_x, across };
      const MapPoint origin = frame.toWorld(from);
      for (const double z : heights)
      {
        sl_sim::Ray ray;
        ray.origin = Eigen::Vector3d(origin.x, origin.y, z);
        ray.direction = Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
        sl_sim::Hit hit;
        // Every surface along the row: the next search starts just past the last hit.
        for (double t = 0.0; sl_sim::intersectScene(scene, ray, hit, t + 1e-4, length); t = hit.t)
          if (!scene.objects[static_cast<std::size_t>(hit.object)].floor)
            points.push_back(along_y ? MapPoint{ from.x, from.y + hit.t } : MapPoint{ from.x + hit.t, from.y });
      }
    }
  }
  return points;
}

void ExploredMap::merge(double origin_x, double origin_y, double resolution, int width, int height,
                        const std::vector<std::int8_t>& cells)
{
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    throw std::invalid_argument("occupancy grid: resolution " + std::to_string(resolution) + " m is not positive");
  if (resolution_ > 0.0 && std::abs(resolution - resolution_) > 1e-9)
    throw std::invalid_argument("occupancy grid: resolution " + std::to_string(resolution) + " m, the map's is " +
                                std::to_string(resolution_) + " m");
  if (width < 0 || height < 0 || cells.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument("occupancy grid: " + std::to_string(cells.size()) + " cells for " +
                                std::to_string(width) + " x " + std::to_string(height));
  const long gx = cornerIndex(origin_x, resolution, "origin x");
  const long gy = cornerIndex(origin_y, resolution, "origin y");
  if (width == 0 || height == 0)
    return;
  resolution_ = resolution;
  growTo(gx, gy, gx + width - 1, gy + height - 1);
  for (int row = 0; row < height; ++row)
  {
    std::int8_t* out = &cells_[static_cast<std::size_t>((gy + row - cy0_) * width_ + (gx - cx0_))];
    const std::int8_t* in = &cells[static_cast<std::size_t>(row) * static_cast<std::size_t>(width)];
    for (int col = 0; col < width; ++col)
      if (in[col] >= 0)
        out[col] = in[col];
  }
}

void ExploredMap::growTo(long x0, long y0, long x1, long y1)
{
  if (!cells_.empty() && x0 >= cx0_ && y0 >= cy0_ && x1 < cx0_ + width_ && y1 < cy0_ + height_)
    return;
  // Grow by a margin, so that a window rolling along copies the map now and then, not every time.
  const long slack = 64;
  const long nx0 = cells_.empty() ? x0 - slack : std::min(cx0_, x0 - slack);
  const long ny0 = cells_.empty() ? y0 - slack : std::min(cy0_, y0 - slack);
  const long nx1 = cells_.empty() ? x1 + slack : std::max(cx0_ + width_ - 1, x1 + slack);
  const long ny1 = cells_.empty() ? y1 + slack : std::max(cy0_ + height_ - 1, y1 + slack);
  const long nw = nx1 - nx0 + 1, nh = ny1 - ny0 + 1;
  std::vector<std::int8_t> grown(static_cast<std::size_t>(nw * nh), -1);
  for (long row = 0; row < height_; ++row)
    std::copy_n(&cells_[static_cast<std::size_t>(row * width_)], width_,
                &grown[static_cast<std::size_t>((cy0_ + row - ny0) * nw + (cx0_ - nx0))]);
  cells_.swap(grown);
  cx0_ = nx0;
  cy0_ = ny0;
  width_ = nw;
  height_ = nh;
}

std::int8_t ExploredMap::at(double x, double y) const
{
  if (cells_.empty())
    return -1;
  const long ix = static_cast<long>(std::floor(x / resolution_ + 1e-9)) - cx0_;
  const long iy = static_cast<long>(std::floor(y / resolution_ + 1e-9)) - cy0_;
  if (ix < 0 || iy < 0 || ix >= width_ || iy >= height_)
    return -1;
  return cells_[static_cast<std::size_t>(iy * width_ + ix)];
}

MapBox ExploredMap::knownBox() const
{
  MapBox box;
  for (long row = 0; row < height_; ++row)
    for (long col = 0; col < width_; ++col)
      if (cells_[static_cast<std::size_t>(row * width_ + col)] >= 0)
      {
        box.add({ (cx0_ + col) * resolution_, (cy0_ + row) * resolution_ });
        box.add({ (cx0_ + col + 1) * resolution_, (cy0_ + row + 1) * resolution_ });
      }
  return box;
}

cv::Point MapPictureLayout::pixel(const MapPoint& p) const
{
  return cv::Point(static_cast<int>(std::floor((p.x - box.min_x) * pixels_per_metre)),
                   top + static_cast<int>(std::floor((box.max_y - p.y) * pixels_per_metre)));
}

MapBox pictureBox(const ExploredMap& map, const std::vector<MapPoint>& path, double margin)
{
  MapBox box = map.knownBox();
  for (const MapPoint& p : path)
    box.add(p);
  if (box.empty())
    box.add({ 0.0, 0.0 });
  box.min_x -= margin;
  box.min_y -= margin;
  box.max_x += margin;
  box.max_y += margin;
  return box;
}

cv::Mat drawMapPicture(const ExploredMap& map, const MapPictureContent& content, MapPictureLayout* layout_out)
{
  MapPictureLayout layout;
  layout.box = pictureBox(map, content.path, std::max(content.margin, 0.05));
  const double w = layout.box.max_x - layout.box.min_x, h = layout.box.max_y - layout.box.min_y;
  layout.pixels_per_metre =
      content.pixels_per_metre > 0.0 ? content.pixels_per_metre : std::clamp(700.0 / std::max(w, h), 20.0, 400.0);
  layout.top = 8 + kLine * static_cast<int>(content.title.size());
  // (rounding: 2.4 m at 100 pixels/m are 240 pixels, not 241)
  const int map_cols = layout.cols = static_cast<int>(std::ceil(w * layout.pixels_per_metre - 1e-6));
  const int map_rows = layout.rows = static_cast<int>(std::ceil(h * layout.pixels_per_metre - 1e-6));
  int baseline = 0;
  const int bar = static_cast<int>(std::lround(layout.pixels_per_metre));  // 1 m
  int cols = std::max({ map_cols, cv::getTextSize(kLegend, kFont, 0.4, 1, &baseline).width + 20, bar + 60 });
  for (const std::string& line : content.title)
    cols = std::max(cols, cv::getTextSize(line, kFont, kFontScale, 1, &baseline).width + 16);
  cv::Mat image(layout.top + map_rows + kBottom, cols, CV_8UC3, cv::Scalar(255, 255, 255));

  for (int r = 0; r < map_rows; ++r)
    for (int c = 0; c < map_cols; ++c)
      image.at<cv::Vec3b>(layout.top + r, c) = shadeOf(map.at(layout.box.min_x + (c + 0.5) / layout.pixels_per_metre,
                                                              layout.box.max_y - (r + 0.5) / layout.pixels_per_metre));
  for (const MapPoint& p : content.outline)
    cv::circle(image, layout.pixel(p), 1, kOutline, cv::FILLED);
  const std::size_t n = content.path.size();
  for (std::size_t i = 1; i < n; ++i)
  {
    const double t = static_cast<double>(i) / static_cast<double>(n - 1);
    cv::line(image, layout.pixel(content.path[i - 1]), layout.pixel(content.path[i]),
             cv::Scalar(255.0 * (1.0 - t), 0.0, 255.0 * t), 2, cv::LINE_AA);
  }
  if (n > 0)
  {
    cv::circle(image, layout.pixel(content.path.front()), 6, cv::Scalar(0, 170, 0), cv::FILLED, cv::LINE_AA);
    cv::circle(image, layout.pixel(content.path.front()), 6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::drawMarker(image, layout.pixel(content.path.back()), cv::Scalar(0, 0, 230), cv::MARKER_TILTED_CROSS, 14, 3);
  }

  for (std::size_t i = 0; i < content.title.size(); ++i)
    cv::putText(image, content.title[i], cv::Point(8, 8 + kLine * static_cast<int>(i) + 12), kFont, kFontScale,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // The scale bar (1 m) and the legend below the map.
  const int y = layout.top + map_rows + 14;
  const int x1 = 10 + bar;
  cv::line(image, cv::Point(10, y), cv::Point(x1, y), cv::Scalar(0, 0, 0), 3);
  cv::line(image, cv::Point(10, y - 6), cv::Point(10, y + 6), cv::Scalar(0, 0, 0), 1);
  cv::line(image, cv::Point(x1, y - 6), cv::Point(x1, y + 6), cv::Scalar(0, 0, 0), 1);
  cv::putText(image, "1 m", cv::Point(x1 + 6, y + 5), kFont, kFontScale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(image, kLegend, cv::Point(10, y + 24), kFont, 0.4, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  if (layout_out)
    *layout_out = layout;
  return image;
}

void writePng(const cv::Mat& image, const std::string& file)
{
  std::vector<unsigned char> bytes;
  if (image.empty() || !cv::imencode(".png", image, bytes, { cv::IMWRITE_PNG_COMPRESSION, 9 }))
    throw std::runtime_error("cannot encode the picture for '" + file + "' as PNG");
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out.good())
    throw std::runtime_error("cannot write the PNG file '" + file + "'");
}
}  // namespace sl_bringup_test
