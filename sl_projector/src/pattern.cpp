#include "sl_projector/pattern.h"

#include <stdexcept>
#include <string>

#include "sl_projector/primitives.h"

namespace sl_projector
{

namespace
{
void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}
}  // namespace

void PatternConfig::validate() const
{
  require(rows >= 3, "rows must be >= 3, got " + std::to_string(rows));
  require(cols >= 3, "cols must be >= 3, got " + std::to_string(cols));
  require(primitive_width >= 3, "primitive_width must be >= 3, got " + std::to_string(primitive_width));
  require(primitive_height >= 3, "primitive_height must be >= 3, got " + std::to_string(primitive_height));
  // One pixel of gap at least, or neighbouring primitives merge into one blob.
  require(gap_x >= 1, "gap_x must be >= 1, got " + std::to_string(gap_x));
  require(gap_y >= 1, "gap_y must be >= 1, got " + std::to_string(gap_y));
  require(offset_x >= 0, "offset_x must be >= 0, got " + std::to_string(offset_x));
  require(offset_y >= 0, "offset_y must be >= 0, got " + std::to_string(offset_y));
  require(projector_width > 0, "projector_width must be > 0, got " + std::to_string(projector_width));
  require(projector_height > 0, "projector_height must be > 0, got " + std::to_string(projector_height));
  const long long right = offset_x + static_cast<long long>(cols) * cellWidth();
  const long long bottom = offset_y + static_cast<long long>(rows) * cellHeight();
  require(right <= projector_width, "cols: " + std::to_string(cols) + " cells of " + std::to_string(cellWidth()) +
                                        " px from offset_x " + std::to_string(offset_x) + " need " +
                                        std::to_string(right) + " px, more than projector_width " +
                                        std::to_string(projector_width));
  require(bottom <= projector_height, "rows: " + std::to_string(rows) + " cells of " + std::to_string(cellHeight()) +
                                          " px from offset_y " + std::to_string(offset_y) + " need " +
                                          std::to_string(bottom) + " px, more than projector_height " +
                                          std::to_string(projector_height));
}

namespace
{
const PatternConfig& validated(const PatternConfig& config)
{
  config.validate();
  return config;
}
}  // namespace

Pattern::Pattern(const PatternConfig& config)
  : config_(validated(config)), array_(config.rows, config.cols, kNumShapes), words_(array_)
{
}

cv::Point Pattern::primitiveOrigin(int row, int col) const
{
  const PatternConfig& c = config_;
  return { c.offset_x + col * c.cellWidth() + c.gap_x / 2, c.offset_y + row * c.cellHeight() + c.gap_y / 2 };
}

cv::Point2d Pattern::primitiveCentroid(int row, int col) const
{
  const PatternConfig& c = config_;
  const cv::Point o = primitiveOrigin(row, col);
  const cv::Point2d centroid = shapeCentroid(array_.value(row, col), c.primitive_width, c.primitive_height);
  double x = o.x + centroid.x;
  double y = o.y + centroid.y;
  if (c.flip_x)
    x = (c.projector_width - 1) - x;
  if (c.flip_y)
    y = (c.projector_height - 1) - y;
  return { x, y };
}

cv::Mat Pattern::render() const
{
  const PatternConfig& c = config_;
  cv::Mat frame(c.projector_height, c.projector_width, CV_8UC1, cv::Scalar(0));
  cv::Mat bitmaps[kNumShapes];
  for (int v = 1; v <= kNumShapes; ++v)
    bitmaps[v - 1] = shapeBitmap(v, c.primitive_width, c.primitive_height);
  for (int r = 0; r < c.rows; ++r)
  {
    for (int col = 0; col < c.cols; ++col)
    {
      const cv::Point o = primitiveOrigin(r, col);
      bitmaps[array_.value(r, col) - 1].copyTo(frame(cv::Rect(o.x, o.y, c.primitive_width, c.primitive_height)));
    }
  }
  const int flip_code = c.flip_x && c.flip_y ? -1 : (c.flip_x ? 1 : 0);
  if (c.flip_x || c.flip_y)
    cv::flip(frame, frame, flip_code);
  return frame;
}

}  // namespace sl_projector
