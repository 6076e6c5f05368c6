#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

#include "sl_decoder/blob_detector.h"
#include "sl_decoder/shape_classifier.h"
#include "sl_rig/primitives.h"

using namespace sl_decoder;

namespace
{
// A bright Gaussian-blurred rectangle centred at (cx, cy) (sub-pixel), drawn 8x supersampled.
void drawBlob(cv::Mat& image, double cx, double cy, double w, double h, double level)
{
  const int s = 8;
  cv::Mat big(image.rows * s, image.cols * s, CV_32F, cv::Scalar(0));
  cv::rectangle(big, cv::Point2d((cx - w / 2 + 0.5) * s, (cy - h / 2 + 0.5) * s),
                cv::Point2d((cx + w / 2 + 0.5) * s - 1, (cy + h / 2 + 0.5) * s - 1), cv::Scalar(level), cv::FILLED);
  cv::GaussianBlur(big, big, cv::Size(0, 0), 0.8 * s);
  cv::Mat small;
  cv::resize(big, small, image.size(), 0, 0, cv::INTER_AREA);
  cv::Mat f;
  image.convertTo(f, CV_32F);
  f += small;
  f.convertTo(image, CV_8U);
}
}  // namespace

TEST(BlobDetector, FindsBlobsWithSubPixelCentroids)
{
  cv::Mat image(120, 160, CV_8UC1, cv::Scalar(20));
  // On the 1/8 px grid of the supersampled drawing, so the truth is exact.
  const double xs[3] = { 30.375, 80.5, 121.75 }, ys[3] = { 40.25, 60.0, 90.625 };
  for (int i = 0; i < 3; ++i)
    drawBlob(image, xs[i], ys[i], 10, 18, 180);
  BlobDetector detector;
  std::vector<Blob> blobs;
  detector.detect(image, blobs);
  ASSERT_EQ(blobs.size(), 3u);
  const ShapeClassifier classifier;
  for (int i = 0; i < 3; ++i)
  {
    // Blobs come out in raster order of their first pixel. The labelling's centroid only weighs
    // pixels above the threshold (a tenth of a pixel at worst); the refined one uses all the light.
    Blob& b = blobs[static_cast<size_t>(i)];
    EXPECT_NEAR(b.u, xs[i], 0.1) << i;
    EXPECT_NEAR(b.v, ys[i], 0.1) << i;
    classifier.refineCentroid(image, b);
    EXPECT_NEAR(b.u, xs[i], 0.02) << i;
    EXPECT_NEAR(b.v, ys[i], 0.02) << i;
    EXPECT_GT(b.contrast, 50.f);
    EXPECT_GE(b.width(), 9);
    EXPECT_GE(b.height(), 17);
  }
}

TEST(BlobDetector, RejectsSpecklesBandsAndHugePatches)
{
  cv::Mat image(200, 300, CV_8UC1, cv::Scalar(30));
  cv::rectangle(image, cv::Rect(20, 20, 2, 2), cv::Scalar(250), cv::FILLED);      // speckle
  cv::rectangle(image, cv::Rect(50, 60, 120, 6), cv::Scalar(250), cv::FILLED);    // horizontal band
  cv::rectangle(image, cv::Rect(200, 100, 10, 18), cv::Scalar(250), cv::FILLED);  // a primitive
  BlobDetector detector;
  std::vector<Blob> blobs;
  detector.detect(image, blobs);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].u, 204.5, 0.3);
  EXPECT_GE(detector.componentCount(), 3);
}

TEST(BlobDetector, EmptyBlackAndSaturatedImagesGiveNothing)
{
  BlobDetector detector;
  std::vector<Blob> blobs;
  detector.detect(cv::Mat(480, 752, CV_8UC1, cv::Scalar(0)), blobs);
  EXPECT_TRUE(blobs.empty());
  detector.detect(cv::Mat(480, 752, CV_8UC1, cv::Scalar(255)), blobs);
  EXPECT_TRUE(blobs.empty());
  detector.detect(cv::Mat(0, 0, CV_8UC1), blobs);
  EXPECT_TRUE(blobs.empty());
  cv::Mat noise(480, 752, CV_8UC1);
  cv::randn(noise, 40, 2);  // dim sensor noise: speckles, not primitives
  detector.detect(noise, blobs);
  EXPECT_LT(blobs.size(), 5u);
}

TEST(BlobDetector, BlobsTouchingTheBorderAreKept)
{
  cv::Mat image(60, 60, CV_8UC1, cv::Scalar(10));
  cv::rectangle(image, cv::Rect(0, 0, 9, 17), cv::Scalar(200), cv::FILLED);
  cv::rectangle(image, cv::Rect(51, 43, 9, 17), cv::Scalar(200), cv::FILLED);
  BlobDetector detector;
  std::vector<Blob> blobs;
  detector.detect(image, blobs);
  ASSERT_EQ(blobs.size(), 2u);
  EXPECT_EQ(blobs[0].x0, 0);
  EXPECT_EQ(blobs[1].x1, 60);
}

// Diagonal stripes (found by fuzzing): every stripe is one component whose box covers most of the
// image. Splitting re-thresholded each part's box, which held the other stripes too, so the parts
// multiplied at every level (over a million after a minute). Splitting looks at a part's own
// pixels only: at most five levels of the components' area.
TEST(BlobDetector, SplittingDiagonalStripesStaysWithinTheirPixels)
{
  const uint8_t period[5] = { 128, 90, 15, 255, 255 };
  cv::Mat image(480, 752, CV_8UC1);
  for (int v = 0; v < image.rows; ++v)
    for (int u = 0; u < image.cols; ++u)
      image.at<uint8_t>(v, u) = period[(u + 5 * image.rows - v) % 5];
  BlobDetector detector;
  detector.setPrimitiveSize(9.0, 17.0, 14.0);  // about the default rig's
  std::vector<Blob> blobs;
  detector.detect(image, blobs);
  EXPECT_GT(detector.splitPixels(), 0) << "the stripes are oversized components; they must be split";
  EXPECT_LE(detector.splitPixels(), 5L * image.rows * image.cols);
  for (const Blob& b : blobs)
    EXPECT_GT(b.level, 0) << "stripes hold no primitive-sized component";
  // Splitting a region twice would give the same part twice.
  for (size_t i = 0; i < blobs.size(); ++i)
    for (size_t j = i + 1; j < blobs.size(); ++j)
      EXPECT_FALSE(blobs[i].u == blobs[j].u && blobs[i].v == blobs[j].v) << i << " " << j;
}

namespace
{
/// True when two blobs agree in every field, floats bit for bit.
::testing::AssertionResult sameBlob(const Blob& a, const Blob& b)
{
  const int ia[] = { a.x0, a.y0, a.x1, a.y1, a.area, a.level, a.shape };
  const int ib[] = { b.x0, b.y0, b.x1, b.y1, b.area, b.level, b.shape };
  const float fa[] = { a.u, a.v, a.contrast, a.correlation, a.margin };
  const float fb[] = { b.u, b.v, b.contrast, b.correlation, b.margin };
  if (std::memcmp(ia, ib, sizeof ia) != 0 || std::memcmp(fa, fb, sizeof fa) != 0)
    return ::testing::AssertionFailure() << "box (" << a.x0 << "," << a.y0 << ")-(" << a.x1 << "," << a.y1 << ") vs ("
                                         << b.x0 << "," << b.y0 << ")-(" << b.x1 << "," << b.y1 << "), u " << a.u
                                         << " vs " << b.u << ", contrast " << a.contrast << " vs " << b.contrast;
  return ::testing::AssertionSuccess();
}

/// Noise, a gradient and blurred rectangles of many sizes: runs of every length, at every offset
/// from the vector blocks and the image borders.
cv::Mat randomScene(cv::RNG& rng, int w, int h)
{
  cv::Mat image(h, w, CV_8UC1);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      image.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(20 + 60.0 * u / w + rng.gaussian(4.0));
  const int n = rng.uniform(5, 60);
  for (int i = 0; i < n; ++i)
  {
    const cv::Point p(rng.uniform(-5, w + 5), rng.uniform(-5, h + 5));
    // Mostly primitive-sized, some merged bands and patches.
    const cv::Size s = i % 4 == 0 ? cv::Size(rng.uniform(1, 40), rng.uniform(1, 30))
                                  : cv::Size(rng.uniform(3, 12), rng.uniform(5, 16));
    cv::rectangle(image, cv::Rect(p, s), cv::Scalar(rng.uniform(40, 256)), cv::FILLED);
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.8);
  return image;
}
}  // namespace

// The local threshold has a portable, an SSE2 and an AVX2 path; they must give the same blobs, bit
// for bit, so that results do not depend on the machine. Sizes and windows vary so that the vector
// blocks, their scalar tails and the image borders all meet runs.
TEST(BlobDetector, VectorPathsGiveIdenticalBlobs)
{
  cv::RNG rng(20261203);
  const BlobDetector::Simd paths[] = { BlobDetector::Simd::Portable, BlobDetector::Simd::Sse2,
                                       BlobDetector::Simd::Avx2 };
  int compared = 0, blobs_seen = 0;
  for (int trial = 0; trial < 60; ++trial)
  {
    const int w = trial < 3 ? 1 + trial * 7 : rng.uniform(20, 400), h = trial < 3 ? 5 : rng.uniform(1, 120);
    const cv::Mat image = randomScene(rng, w, h);
    DecoderConfig config;
    config.threshold_window = 2 * rng.uniform(1, 12) + 1;
    config.threshold_offset = rng.uniform(0.0, 8.0);
    config.split_merged = trial % 2 == 0;
    std::vector<Blob> reference, blobs;
    BlobDetector detector(config);
    detector.setPrimitiveSize(5.0, 9.0, 7.0);
    ASSERT_EQ(detector.useSimd(BlobDetector::Simd::Portable), BlobDetector::Simd::Portable);
    detector.detect(image, reference);
    blobs_seen += static_cast<int>(reference.size());
    for (BlobDetector::Simd path : paths)
    {
      if (detector.useSimd(path) != path)
        continue;  // this CPU lacks it (then it cannot differ here either)
      detector.detect(image, blobs);
      ASSERT_EQ(blobs.size(), reference.size()) << "trial " << trial << " path " << static_cast<int>(path);
      for (size_t i = 0; i < blobs.size(); ++i)
        ASSERT_TRUE(sameBlob(blobs[i], reference[i])) << "trial " << trial << " blob " << i;
      ++compared;
    }
  }
  EXPECT_GE(compared, 120) << "the portable and SSE2 paths run everywhere on x86-64";
  EXPECT_GT(blobs_seen, 500);
}

TEST(BlobDetector, DeferredCentroidsAreTheCentroidsDetectGives)
{
  // The decoder asks for the labelling's centroid only for the blobs left unidentified: they get
  // the same floats as detect() gives; the others' stay as the caller set them.
  cv::RNG rng(20261205);
  int checked = 0;
  for (int trial = 0; trial < 20; ++trial)
  {
    const cv::Mat image = randomScene(rng, rng.uniform(40, 300), rng.uniform(20, 120));
    DecoderConfig config;
    config.split_merged = trial % 2 == 0;
    BlobDetector detector(config);
    detector.setPrimitiveSize(5.0, 9.0, 7.0);
    std::vector<Blob> reference, blobs;
    detector.detect(image, reference);
    detector.detectBoxes(image, blobs);
    ASSERT_EQ(blobs.size(), reference.size());
    for (size_t i = 0; i < blobs.size(); ++i)
    {
      ASSERT_EQ(std::isnan(blobs[i].u), blobs[i].level == 0) << "whole components wait for centroids()";
      if (i % 3 == 0 && blobs[i].level == 0)
      {
        blobs[i].shape = 1;
        blobs[i].u = blobs[i].v = -7.f;  // as if refined
      }
      else if (i % 3 == 1)
        blobs[i].shape = 2;  // identified, but its refinement found no light: it keeps the labelling's
    }
    detector.centroids(blobs);
    for (size_t i = 0; i < blobs.size(); ++i)
    {
      if (blobs[i].shape == 1)
      {
        EXPECT_EQ(blobs[i].u, -7.f) << "a blob with a shape keeps its centroid";
        continue;
      }
      ASSERT_EQ(std::memcmp(&blobs[i].u, &reference[i].u, sizeof(float)), 0) << "trial " << trial << " blob " << i;
      ASSERT_EQ(std::memcmp(&blobs[i].v, &reference[i].v, sizeof(float)), 0) << "trial " << trial << " blob " << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(ShapeClassifier, Avx2PathsGiveIdenticalCorrelationsAndCentroids)
{
  // Boxes of every size a primitive takes (and some it does not), anywhere in images of varied
  // widths, up against every border, for grids with an even and an odd number of rows (the AVX2
  // path sums rows in pairs) and one the AVX2 resampling does not take: the AVX2 and the portable
  // paths agree bit for bit. So do the refined centroids (AVX2, SSE2 and scalar sums).
  cv::RNG rng(20261204);
  const int grids[][2] = { { 8, 14 }, { 8, 13 }, { 8, 3 }, { 7, 14 } };
  bool avx2 = false;
  int compared = 0, refined = 0;
  for (const auto& grid : grids)
  {
    DecoderConfig config;
    config.template_width = grid[0];
    config.template_height = grid[1];
    ShapeClassifier classifier(config);
    avx2 = classifier.useAvx2(true);
    for (int trial = 0; trial < 40; ++trial)
    {
      const int w = rng.uniform(2, 200), h = rng.uniform(2, 80);
      const cv::Mat image = randomScene(rng, w, h);
      for (int k = 0; k < 50; ++k)
      {
        Blob box;
        box.x0 = rng.uniform(0, w);
        box.y0 = rng.uniform(0, h);
        box.x1 = std::min(w, box.x0 + rng.uniform(1, k % 10 == 0 ? 140 : 18));
        box.y1 = std::min(h, box.y0 + rng.uniform(1, 24));
        Blob vector = box, portable = box;
        classifier.useAvx2(true);
        classifier.classify(image, vector);
        classifier.refineCentroid(image, vector, k % 4);
        classifier.useAvx2(false);
        classifier.classify(image, portable);
        classifier.refineCentroid(image, portable, k % 4);
        const std::string where = "grid " + std::to_string(grid[0]) + " x " + std::to_string(grid[1]) + ", trial " +
                                  std::to_string(trial) + ", box " + std::to_string(box.x0) + ".." +
                                  std::to_string(box.x1) + " x " + std::to_string(box.y0) + ".." +
                                  std::to_string(box.y1);
        ASSERT_EQ(std::memcmp(&vector.correlation, &portable.correlation, sizeof(float)), 0) << where;
        ASSERT_EQ(std::memcmp(&vector.margin, &portable.margin, sizeof(float)), 0) << where;
        ASSERT_EQ(vector.shape, portable.shape) << where;
        ASSERT_EQ(std::memcmp(&vector.u, &portable.u, sizeof(float)), 0) << where;
        ASSERT_EQ(std::memcmp(&vector.v, &portable.v, sizeof(float)), 0) << where;
        compared += portable.correlation != 0.f ? 1 : 0;
        refined += portable.u != box.u ? 1 : 0;
      }
    }
  }
  EXPECT_GT(compared, 4000) << "most boxes hold some contrast";
  EXPECT_GT(refined, 4000) << "most boxes hold some light";
  if (!avx2)
    GTEST_SKIP() << "this CPU has no AVX2: only the portable path ran";
}

// The labelling's centroid weighs each foreground pixel by its value minus the mean of its window
// (the image's part of it): computed here with OpenCV's box filter, independently of the row pass
// and of the window sums centroids() forms again. Blobs at the borders clip their windows.
TEST(BlobDetector, CentroidsWeighPixelsByValueMinusTheirWindowsMean)
{
  cv::Mat image(100, 150, CV_8UC1, cv::Scalar(30));
  const double xs[4] = { 4.5, 60.25, 100.0, 145.0 }, ys[4] = { 50.0, 3.5, 60.75, 95.5 };
  for (int i = 0; i < 4; ++i)
    drawBlob(image, xs[i], ys[i], 7, 11, 150);
  DecoderConfig config;
  config.threshold_window = 13;
  BlobDetector detector(config);
  std::vector<Blob> blobs;
  detector.detect(image, blobs);
  ASSERT_EQ(blobs.size(), 4u);
  cv::Mat sums, area;
  const cv::Size window(config.threshold_window, config.threshold_window);
  cv::boxFilter(image, sums, CV_64F, window, cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  cv::boxFilter(cv::Mat::ones(image.size(), CV_64F), area, CV_64F, window, cv::Point(-1, -1), false,
                cv::BORDER_CONSTANT);
  for (const Blob& b : blobs)
  {
    double sw = 0.0, swx = 0.0, swy = 0.0;
    for (int y = b.y0; y < b.y1; ++y)
      for (int x = b.x0; x < b.x1; ++x)
      {
        const double mean = sums.at<double>(y, x) / area.at<double>(y, x);
        const double weight = image.at<uint8_t>(y, x) - mean;
        if (weight <= config.threshold_offset)
          continue;  // background
        sw += weight;
        swx += weight * x;
        swy += weight * y;
      }
    ASSERT_GT(sw, 0.0);
    EXPECT_NEAR(b.u, swx / sw, 1e-3) << "blob at " << b.x0 << ", " << b.y0;
    EXPECT_NEAR(b.v, swy / sw, 1e-3) << "blob at " << b.x0 << ", " << b.y0;
  }
}

// The vector light sums take boxes up to 127 x 256 px (16 px wide ones two rows at a time): at full
// light within a black rim, their sums are at their largest (int32 lanes), and the scalar sums take
// over beyond.
TEST(ShapeClassifier, LargestBoxesGiveIdenticalCentroids)
{
  ShapeClassifier classifier;
  for (const cv::Size& size : { cv::Size(127, 256), cv::Size(126, 255), cv::Size(128, 256), cv::Size(127, 257),
                                cv::Size(16, 256), cv::Size(15, 255), cv::Size(16, 257) })
  {
    cv::Mat image(300, 160, CV_8UC1, cv::Scalar(0));
    image(cv::Rect(1, 1, size.width - 2, size.height - 2)).setTo(255);
    Blob box;
    box.x1 = size.width;
    box.y1 = size.height;
    Blob vector = box, portable = box;
    classifier.useAvx2(true);
    classifier.refineCentroid(image, vector, 0);
    classifier.useAvx2(false);
    classifier.refineCentroid(image, portable, 0);
    EXPECT_EQ(std::memcmp(&vector.u, &portable.u, sizeof(float)), 0) << size;
    EXPECT_EQ(std::memcmp(&vector.v, &portable.v, sizeof(float)), 0) << size;
    EXPECT_FLOAT_EQ(portable.u, (size.width - 1) / 2.f) << size;
    EXPECT_FLOAT_EQ(portable.v, (size.height - 1) / 2.f) << size;
  }
}

#if defined(__x86_64__)
// The correlations and refined centroids of fixed boxes, bit for bit as the classifier has always
// given them (decodes are compared bit for bit across versions). The sums' order decides the last
// bits: a change of it, or a compiler allowed to reorder float sums, fails here. (x86-64 only:
// compilers elsewhere may fuse multiply-adds.)
TEST(ShapeClassifier, CorrelationsKeepTheirBits)
{
  cv::Mat image(40, 64, CV_8UC1);
  for (int v = 0; v < image.rows; ++v)
    for (int u = 0; u < image.cols; ++u)
      image.at<uint8_t>(v, u) = static_cast<uint8_t>(20 + (u * 7 + v * 13) % 9);
  cv::rectangle(image, cv::Rect(5, 4, 6, 11), cv::Scalar(200), cv::FILLED);
  cv::rectangle(image, cv::Rect(7, 8, 2, 3), cv::Scalar(60), cv::FILLED);
  cv::rectangle(image, cv::Rect(20, 20, 8, 12), cv::Scalar(150), cv::FILLED);
  cv::rectangle(image, cv::Rect(20, 20, 4, 6), cv::Scalar(90), cv::FILLED);
  cv::rectangle(image, cv::Rect(56, 10, 8, 14), cv::Scalar(230), cv::FILLED);
  cv::rectangle(image, cv::Rect(60, 16, 4, 8), cv::Scalar(40), cv::FILLED);
  for (int s = 1; s <= 4; ++s)
  {
    cv::Mat roi = image(cv::Rect(30 + 8 * (s - 1), 2 + 3 * s, 7, 13));
    sl_projector::shapeTemplate(s, 7, 13, 0.8).convertTo(roi, CV_8U, 200.0, 25.0);
  }
  struct Expected
  {
    int tw, th, x0, y0, x1, y1, shape;
    uint32_t correlation, margin, u, v;  // bits
  };
  const Expected expected[] = {
    { 8, 14, 4, 3, 12, 16, 0, 0x3cdd8518u, 0x3a18dec0u, 0x40f0095eu, 0x411006beu },
    { 8, 14, 19, 19, 29, 33, 0, 0x3e18233bu, 0x3dd6cbaau, 0x41be1d76u, 0x41cf3233u },
    { 8, 14, 55, 9, 64, 25, 2, 0x3ed64623u, 0x3e6c5981u, 0x42687774u, 0x418bc460u },
    { 8, 14, 3, 2, 30, 35, 0, 0x3e7022f3u, 0x3db2afdcu, 0x418cdfd8u, 0x418040e2u },
    { 8, 14, 30, 5, 37, 18, 1, 0x3f7e64f9u, 0x3f61f751u, 0x4205f16fu, 0x4126651eu },
    { 8, 14, 38, 8, 45, 21, 2, 0x3f7e5b0cu, 0x3f57da85u, 0x42242b1eu, 0x4152d0edu },
    { 8, 14, 46, 11, 53, 24, 3, 0x3f7e4da2u, 0x3f57d656u, 0x4244192bu, 0x418e5a78u },
    { 8, 14, 54, 14, 61, 27, 4, 0x3f7e69f2u, 0x3f6088bfu, 0x426436e4u, 0x419928dbu },
    { 8, 13, 19, 19, 29, 33, 0, 0x3e13fcf5u, 0x3dcd5cc4u, 0x41be1d76u, 0x41cf3233u },
    { 8, 13, 38, 8, 45, 21, 2, 0x3f7edeeau, 0x3f55075bu, 0x42242b1eu, 0x4152d0edu },
    { 7, 13, 3, 2, 30, 35, 0, 0x3e9cb2cdu, 0x3e1614dau, 0x418cdfd8u, 0x418040e2u },
    { 7, 13, 46, 11, 53, 24, 3, 0x3f7fff93u, 0x3f565a7du, 0x4244192bu, 0x418e5a78u },
  };
  auto bits = [](float f)
  {
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
  };
  for (bool avx2 : { false, true })
    for (const Expected& e : expected)
    {
      DecoderConfig config;
      config.template_width = e.tw;
      config.template_height = e.th;
      ShapeClassifier classifier(config);
      classifier.useAvx2(avx2);
      Blob b;
      b.x0 = e.x0;
      b.y0 = e.y0;
      b.x1 = e.x1;
      b.y1 = e.y1;
      classifier.classify(image, b);
      classifier.refineCentroid(image, b);
      const std::string where = std::to_string(e.tw) + " x " + std::to_string(e.th) + " box at " +
                                std::to_string(e.x0) + ", " + std::to_string(e.y0) + (avx2 ? " (AVX2)" : "");
      EXPECT_EQ(b.shape, e.shape) << where;
      EXPECT_EQ(bits(b.correlation), e.correlation) << where << ": " << b.correlation;
      EXPECT_EQ(bits(b.margin), e.margin) << where << ": " << b.margin;
      EXPECT_EQ(bits(b.u), e.u) << where << ": " << b.u;
      EXPECT_EQ(bits(b.v), e.v) << where << ": " << b.v;
    }
}
#endif

// The classifier's grid lives in arrays of 64: a template beyond them is refused by name, also when
// the config did not pass DecoderConfig::validate().
TEST(ShapeClassifier, TemplateBeyondItsGridIsRefusedByName)
{
  DecoderConfig config;
  config.template_width = 65;
  try
  {
    ShapeClassifier classifier(config);
    FAIL() << "a 65-wide template was accepted";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("template_width"), std::string::npos) << e.what();
  }
  config.template_width = 64;
  config.template_height = 2;
  EXPECT_THROW(ShapeClassifier{ config }, std::invalid_argument);
}
