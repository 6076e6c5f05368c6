// The lens fit on synthetic blur samples (exact, noisy with outliers, refused for too few, one-sided
// or depth-independent samples) and the edge measurement on a drawn, blurred checkerboard. The fit
// on rendered boards and in the full calibration is in sl_evaluation_test (CalibrationLens.*).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "sl_calibration/lens_blur.h"

using namespace sl_calibration;

namespace
{
constexpr double kFocalPx = 1492.0, kPitch = 6.0e-6;

/// Blur samples of a thin lens focused at @p focus at @p f_number, base blur @p base, at depths
/// 0.35 to 1.2 m.
std::vector<BlurSample> thinLensSamples(double focus, double f_number, double base, int n = 60)
{
  sl_projector::LensOptics lens{ focus, f_number, kPitch };
  std::vector<BlurSample> s;
  for (int i = 0; i < n; ++i)
  {
    const double depth = 0.35 + 0.85 * i / (n - 1);
    const double d = lens.defocusDiameter(kFocalPx, depth) / 4.0;
    s.push_back(BlurSample{ depth, std::sqrt(base * base + d * d) });
  }
  return s;
}
}  // namespace

TEST(LensFit, RecoversAThinLensFromExactSamples)
{
  for (double focus : { 0.5, 0.675, 0.9 })
  {
    const LensFit fit = fitLensOptics(thinLensSamples(focus, 2.0, 0.4), kFocalPx, kPitch);
    ASSERT_TRUE(fit.valid) << fit.note;
    EXPECT_NEAR(fit.lens.focus_distance, focus, 1e-4 * focus);
    EXPECT_NEAR(fit.lens.f_number, 2.0, 1e-3);
    EXPECT_NEAR(fit.base_sigma, 0.4, 1e-3);
    EXPECT_LT(fit.rms, 1e-4);
    EXPECT_EQ(fit.lens.pixel_pitch, kPitch);
  }
}

TEST(LensFit, NoiseAndOutliers)
{
  std::vector<BlurSample> s = thinLensSamples(0.6, 1.4, 0.5, 400);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (size_t i = 0; i < s.size(); ++i)
    s[i].sigma = i % 20 == 0 ? s[i].sigma + 1.5 : s[i].sigma + noise(rng);  // 5 % far off
  const LensFit fit = fitLensOptics(s, kFocalPx, kPitch);
  std::cout << fit.summary("noisy");
  std::printf("focus %.5f m, f/%.4f\n", fit.lens.focus_distance, fit.lens.f_number);
  ASSERT_TRUE(fit.valid) << fit.note;
  // Measured: 0.59864 m, f/1.4012; the 20 samples far off left out.
  EXPECT_NEAR(fit.lens.focus_distance, 0.6, 0.0019);
  EXPECT_NEAR(fit.lens.f_number, 1.4, 0.0017);
  EXPECT_EQ(fit.samples, 380);
}

TEST(LensFit, RefusedWithTheReason)
{
  const LensFit few = fitLensOptics(thinLensSamples(0.6, 2.0, 0.4, 9), kFocalPx, kPitch);
  EXPECT_FALSE(few.valid);
  EXPECT_EQ(few.note, "9 blur samples (need 10)");
  // Only nearer than the focus.
  std::vector<BlurSample> near = thinLensSamples(0.9, 2.0, 0.4);
  near.erase(std::remove_if(near.begin(), near.end(), [](const BlurSample& b) { return b.depth > 0.8; }), near.end());
  const LensFit one_side = fitLensOptics(near, kFocalPx, kPitch);
  EXPECT_FALSE(one_side.valid);
  EXPECT_NE(one_side.note.find("do not lie on both sides of the focus"), std::string::npos) << one_side.note;
  EXPECT_NE(one_side.summary("camera").find("camera lens optics not estimated: the samples (0.35 to 0.80 m)"),
            std::string::npos)
      << one_side.summary("camera");
  // The same blur at every depth: no lens to fit.
  std::vector<BlurSample> flat = thinLensSamples(0.6, 2.0, 0.4);
  for (BlurSample& b : flat)
    b.sigma = 0.7;
  const LensFit none = fitLensOptics(flat, kFocalPx, kPitch);
  EXPECT_FALSE(none.valid);
  EXPECT_NE(none.note.find("no defocus blur measured"), std::string::npos) << none.note;
  // Bad samples are left out, not fitted.
  std::vector<BlurSample> bad(20, BlurSample{ -1.0, 1.0 });
  EXPECT_EQ(fitLensOptics(bad, kFocalPx, kPitch).samples, 0);
}

// A drawn checkerboard blurred by a known Gaussian: every edge measures that sigma.
TEST(BoardEdgeBlur, MeasuresTheBlurOfADrawnBoard)
{
  const Board board = parseBoardSize("7x5", 0.02);
  const int square = 40, x0 = 100, y0 = 60;
  cv::Mat image(400, 500, CV_8UC1, cv::Scalar(200));
  for (int r = 0; r < board.rows + 1; ++r)
    for (int c = 0; c < board.cols + 1; ++c)
      if ((r + c) % 2 == 0)
        cv::rectangle(image, cv::Rect(x0 + c * square, y0 + r * square, square, square), cv::Scalar(20), cv::FILLED);
  for (double sigma : { 1.0, 2.0 })
  {
    cv::Mat blurred;
    cv::GaussianBlur(image, blurred, cv::Size(0, 0), sigma);
    std::vector<cv::Point2f> corners;
    ASSERT_TRUE(findBoardCorners(blurred, board, corners)) << sigma;
    const std::vector<EdgeBlur> edges = measureBoardEdgeBlur(blurred, board, corners);
    // 7 x 5 inner corners: 6 x 5 + 7 x 4 = 58 edges.
    EXPECT_EQ(edges.size(), 58u) << sigma;
    std::vector<double> s;
    for (const EdgeBlur& e : edges)
      s.push_back(e.sigma);
    std::sort(s.begin(), s.end());
    // Measured: 1.024 px (sigma 1), 2.008 px (sigma 2) on every edge: the drawn edge's pixel adds a little.
    std::cout << "sigma " << sigma << ": median " << s[s.size() / 2] << ", range " << s.front() << " to " << s.back()
              << "\n";
    EXPECT_NEAR(s[s.size() / 2], sigma, sigma < 1.5 ? 0.034 : 0.012) << sigma;
    EXPECT_NEAR(edges[0].on_board.x, 0.01, 1e-6);  // the first edge: between corners 0 and 1
  }
  // Corners that are not the board's: nothing measured.
  EXPECT_TRUE(measureBoardEdgeBlur(image, board, std::vector<cv::Point2f>(3)).empty());
}
