#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "sl_rig/primitives.h"

using namespace sl_projector;

namespace
{
constexpr int kSuper = 8;  // supersampling of one projector pixel

/// Projector cell (shape centred with one pixel of background around it, 7 x 11 px) seen through
/// a blur of @p sigma projector px and resampled to @p scale camera px per projector px (0.5 is
/// a 2x down-sampling), the shape shifted by (dx, dy) projector px.
cv::Mat observe(int value, double dx, double dy, double sigma, double scale)
{
  cv::Mat cell(11, 7, CV_32F, cv::Scalar(0));
  cv::Mat bitmap;
  shapeBitmap(value).convertTo(bitmap, CV_32F, 1.0 / 255.0);
  bitmap.copyTo(cell(cv::Rect(1, 1, 5, 9)));
  cv::Mat fine;
  cv::resize(cell, fine, cv::Size(), kSuper, kSuper, cv::INTER_NEAREST);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, dx * kSuper, 0, 1, dy * kSuper);
  cv::warpAffine(fine, fine, shift, fine.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), sigma * kSuper);
  cv::Mat out;
  cv::resize(fine, out, cv::Size(), scale / kSuper, scale / kSuper, cv::INTER_AREA);
  return out;
}

/// What the decoder does: threshold at half the peak, take the bounding box, resample it to the
/// template grid.
cv::Mat cropToTemplate(const cv::Mat& observed, cv::Size tsize)
{
  double peak = 0.0;
  cv::minMaxLoc(observed, nullptr, &peak);
  const cv::Rect box = cv::boundingRect(observed > 0.5 * peak);
  cv::Mat t;
  cv::resize(observed(box), t, tsize, 0, 0, cv::INTER_LINEAR);
  return t;
}

struct Stats
{
  double min_self = 1.0;
  double max_cross = -1.0;
  double min_margin = 2.0;
};

// Worst case over sub-pixel phases of the correlation with the right template, the best wrong
// template and their difference.
Stats matchStats(double sigma, double scale, bool crop)
{
  const cv::Size tsize(10, 18);
  cv::Mat templates[kNumShapes];
  for (int v = 1; v <= kNumShapes; ++v)
    templates[v - 1] = crop ? shapeTemplate(v, tsize.width, tsize.height, 1.0) : observe(v, 0, 0, sigma, scale);
  Stats s;
  for (int v = 1; v <= kNumShapes; ++v)
    for (double dx : { 0.0, 0.25, 0.5, 0.75 })
      for (double dy : { 0.0, 0.25, 0.5, 0.75 })
      {
        const cv::Mat seen = observe(v, crop ? dx : 0.0, crop ? dy : 0.0, sigma, scale);
        const cv::Mat probe = crop ? cropToTemplate(seen, tsize) : seen;
        double self = 0.0, cross = -1.0;
        for (int w = 1; w <= kNumShapes; ++w)
        {
          const double ncc = normalizedCrossCorrelation(probe, templates[w - 1]);
          if (w == v)
            self = ncc;
          else
            cross = std::max(cross, ncc);
        }
        s.min_self = std::min(s.min_self, self);
        s.max_cross = std::max(s.max_cross, cross);
        s.min_margin = std::min(s.min_margin, self - cross);
      }
  return s;
}
}  // namespace

TEST(Primitives, ShapesAreConnectedFullBoxAndDistinct)
{
  for (int v = 1; v <= kNumShapes; ++v)
  {
    const cv::Mat b = shapeBitmap(v);
    ASSERT_EQ(b.rows, 9);
    ASSERT_EQ(b.cols, 5);
    cv::Mat labels;
    EXPECT_EQ(cv::connectedComponents(b, labels, 4), 2) << "shape " << v << " must be one component";
    EXPECT_EQ(cv::boundingRect(b), cv::Rect(0, 0, 5, 9)) << "shape " << v;
    EXPECT_EQ(cv::countNonZero(b), 33) << "equal areas keep blob brightness independent of the shape";
    // The horizontal centroid (what depth is computed from) is the middle column for every shape.
    EXPECT_NEAR(shapeCentroid(v).x, 2.0, 1e-12);
    for (int w = v + 1; w <= kNumShapes; ++w)
      EXPECT_GT(cv::countNonZero(b != shapeBitmap(w)), 0) << v << " vs " << w;
  }
  // Vertical centroids: W on top pulls it up, W at the bottom pulls it down.
  EXPECT_NEAR(shapeCentroid(1).y, (15 * 1.0 + 9 * 4.0 + 9 * 7.0) / 33.0, 1e-12);
  EXPECT_NEAR(shapeCentroid(3).y, 8.0 - shapeCentroid(1).y, 1e-12);
}

TEST(Primitives, OtherSizesStayConnected)
{
  for (int w = 3; w <= 12; ++w)
    for (int h = 3; h <= 18; ++h)
      for (int v = 1; v <= kNumShapes; ++v)
      {
        const cv::Mat b = shapeBitmap(v, w, h);
        cv::Mat labels;
        EXPECT_EQ(cv::connectedComponents(b, labels, 8), 2) << v << " at " << w << "x" << h;
        EXPECT_EQ(cv::boundingRect(b), cv::Rect(0, 0, w, h));
      }
  EXPECT_THROW(shapeBitmap(0), std::invalid_argument);
  EXPECT_THROW(shapeBitmap(5), std::invalid_argument);
  EXPECT_THROW(shapeBitmap(1, 2, 9), std::invalid_argument);
}

// The criterion: blur sigma 1 px, then 2x down-sampling; every shape is then compared with
// the others on the same cell window. A shape correlates with itself at 1 by construction; the
// margin to the best other shape must stay large.
TEST(Primitives, DistinctAfterBlurAndDownSampling)
{
  const Stats s = matchStats(1.0, 0.5, false);
  std::cout << "cell window, sigma 1, 2x down: max cross " << s.max_cross << "\n";
  EXPECT_NEAR(s.min_self, 1.0, 1e-9);
  EXPECT_LT(s.max_cross, 0.75);
}

// What the decoder does, including misalignment: the blob's bounding box resampled to a template
// grid and correlated with the ideal templates, over all quarter-pixel phases, at the camera scales
// of the working range (1.5 to 3 camera px per projector px) with defocus blur up to 1.5 projector
// px. The margin (right template minus best wrong one) must stay above 0.3: sensor noise at the
// simulator's default settings moves a blob's NCC by a few hundredths, an order of magnitude less.
// Even at a harsh 2x down-sampling (a primitive only 2.5 x 4.5 px) the right template
// must still win everywhere.
TEST(Primitives, DecoderMatchingMarginAcrossBlurAndPhase)
{
  for (double scale : { 1.5, 3.0 })
    for (double sigma : { 0.5, 1.0, 1.5 })
    {
      const Stats s = matchStats(sigma, scale, true);
      std::cout << "scale " << scale << " sigma " << sigma << ": min self " << s.min_self << ", max cross "
                << s.max_cross << ", min margin " << s.min_margin << "\n";
      EXPECT_GT(s.min_margin, 0.3) << "scale " << scale << " sigma " << sigma;
      EXPECT_LT(s.max_cross, 0.5) << "scale " << scale << " sigma " << sigma;
    }
  const Stats harsh = matchStats(1.0, 0.5, true);
  std::cout << "scale 0.5 sigma 1: min margin " << harsh.min_margin << "\n";
  EXPECT_GT(harsh.min_margin, 0.1);
}

TEST(Primitives, TemplatesAndNcc)
{
  const cv::Mat t = shapeTemplate(1, 10, 18);
  ASSERT_EQ(t.type(), CV_32F);
  ASSERT_EQ(t.size(), cv::Size(10, 18));
  // Top band is fully covered, the bottom-left corner not at all.
  EXPECT_NEAR(t.at<float>(0, 0), 1.0f, 1e-6f);
  EXPECT_NEAR(t.at<float>(17, 0), 0.0f, 1e-6f);
  EXPECT_NEAR(normalizedCrossCorrelation(t, t), 1.0, 1e-9);
  EXPECT_NEAR(normalizedCrossCorrelation(t, 1.0 - t), -1.0, 1e-9);
  EXPECT_EQ(normalizedCrossCorrelation(t, cv::Mat::ones(18, 10, CV_32F)), 0.0);
}
