#include "sl_rig/pattern.h"

#include <stdexcept>
#include <string>

#include "sl_rig/primitives.h"

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
  require(projector_width <= kMaxImageSide,
          "projector_width must be <= " + std::to_string(kMaxImageSide) + ", got " + std::to_string(projector_width));
  require(projector_height <= kMaxImageSide,
          "projector_height must be <= " + std::to_string(kMaxImageSide) + ", got " + std::to_string(projector_height));
  // Each of these alone must fit in the frame, so the sums and products below cannot overflow
  // (primitive_width 2147483647 with gap_x 1 once wrapped to a negative cell width and passed).
  auto fitsIn = [](const char* field, int value, const char* side_name, int side)
  {
    require(value <= side, std::string(field) + " must be <= " + side_name + " (" + std::to_string(side) + "), got " +
                               std::to_string(value));
  };
  fitsIn("primitive_width", primitive_width, "projector_width", projector_width);
  fitsIn("gap_x", gap_x, "projector_width", projector_width);
  fitsIn("offset_x", offset_x, "projector_width", projector_width);
  fitsIn("primitive_height", primitive_height, "projector_height", projector_height);
  fitsIn("gap_y", gap_y, "projector_height", projector_height);
  fitsIn("offset_y", offset_y, "projector_height", projector_height);
  const long long cell_w = static_cast<long long>(primitive_width) + gap_x;
  const long long cell_h = static_cast<long long>(primitive_height) + gap_y;
  const long long right = offset_x + static_cast<long long>(cols) * cell_w;
  const long long bottom = offset_y + static_cast<long long>(rows) * cell_h;
  require(right <= projector_width, "cols: " + std::to_string(cols) + " cells of " + std::to_string(cell_w) +
                                        " px from offset_x " + std::to_string(offset_x) + " need " +
                                        std::to_string(right) + " px, more than projector_width " +
                                        std::to_string(projector_width));
  require(bottom <= projector_height, "rows: " + std::to_string(rows) + " cells of " + std::to_string(cell_h) +
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
