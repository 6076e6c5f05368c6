#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

#include <sl_testing/errors.h>

#include "sl_rig/pattern.h"
#include "sl_rig/primitives.h"

using namespace sl_projector;
using sl_testing::refusedNaming;
using sl_testing::validationError;

TEST(Pattern, DefaultLayoutIsThePrototypes)
{
  const Pattern p;
  const cv::Mat f = p.render();
  ASSERT_EQ(f.type(), CV_8UC1);
  ASSERT_EQ(f.cols, 480);
  ASSERT_EQ(f.rows, 320);
  // 64 x 16 cells of 7 x 15 px: 448 x 240 px, top-left aligned; nothing outside.
  EXPECT_EQ(cv::countNonZero(f(cv::Rect(448, 0, 32, 320))), 0);
  EXPECT_EQ(cv::countNonZero(f(cv::Rect(0, 240, 480, 80))), 0);
  EXPECT_EQ(cv::countNonZero(f), 16 * 64 * 33);
  // Each primitive's box holds exactly its shape; the gaps are dark.
  for (int r = 0; r < 16; ++r)
    for (int c = 0; c < 64; ++c)
    {
      const cv::Point o = p.primitiveOrigin(r, c);
      EXPECT_EQ(o, cv::Point(7 * c + 1, 15 * r + 3));
      const cv::Mat box = f(cv::Rect(o.x, o.y, 5, 9));
      ASSERT_EQ(cv::countNonZero(box != shapeBitmap(p.array().value(r, c))), 0) << r << "," << c;
    }
  // One blob per primitive (8-connectivity): the gaps separate them.
  cv::Mat labels;
  EXPECT_EQ(cv::connectedComponents(f, labels, 8), 16 * 64 + 1);
}

TEST(Pattern, CentroidsMatchTheRenderedBlobs)
{
  for (bool fx : { false, true })
    for (bool fy : { false, true })
    {
      PatternConfig c;
      c.offset_x = 10;
      c.offset_y = 20;
      c.flip_x = fx;
      c.flip_y = fy;
      const Pattern p(c);
      const cv::Mat f = p.render();
      for (int r : { 0, 7, 15 })
        for (int col : { 0, 31, 63 })
        {
          const cv::Point2d centroid = p.primitiveCentroid(r, col);
          const cv::Rect window(static_cast<int>(centroid.x) - 3, static_cast<int>(centroid.y) - 6, 7, 13);
          const cv::Moments m = cv::moments(f(window), true);
          EXPECT_NEAR(window.x + m.m10 / m.m00, centroid.x, 1e-9) << fx << fy << " " << r << "," << col;
          EXPECT_NEAR(window.y + m.m01 / m.m00, centroid.y, 1e-9) << fx << fy << " " << r << "," << col;
        }
    }
}

TEST(Pattern, FlipsMirrorTheFrame)
{
  PatternConfig c;
  const cv::Mat plain = Pattern(c).render();
  c.flip_x = true;
  c.flip_y = true;
  cv::Mat flipped = Pattern(c).render();
  cv::Mat back;
  cv::flip(flipped, back, -1);
  EXPECT_EQ(cv::countNonZero(back != plain), 0);
  EXPECT_GT(cv::countNonZero(flipped != plain), 0);
}

TEST(Pattern, OtherGeometries)
{
  PatternConfig c;
  c.rows = 10;
  c.cols = 30;
  c.primitive_width = 7;
  c.primitive_height = 12;
  c.gap_x = 3;
  c.gap_y = 5;
  c.projector_width = 320;
  c.projector_height = 200;
  const cv::Mat f = Pattern(c).render();
  EXPECT_EQ(f.size(), cv::Size(320, 200));
  cv::Mat labels;
  EXPECT_EQ(cv::connectedComponents(f, labels, 8), 10 * 30 + 1);
}

TEST(Pattern, InvalidConfigurationsNameTheField)
{
  EXPECT_TRUE(refusedNaming<PatternConfig>("cols", [](auto& c) { c.cols = 69; }));  // 69 * 7 = 483 > 480
  EXPECT_TRUE(refusedNaming<PatternConfig>("rows", [](auto& c) { c.rows = 22; }));  // 330 > 320
  EXPECT_TRUE(refusedNaming<PatternConfig>("gap_x", [](auto& c) { c.gap_x = 0; }));
  EXPECT_TRUE(refusedNaming<PatternConfig>("primitive_height", [](auto& c) { c.primitive_height = 2; }));
  EXPECT_TRUE(refusedNaming<PatternConfig>("offset_x", [](auto& c) { c.offset_x = -1; }));
  EXPECT_TRUE(refusedNaming<PatternConfig>("projector_width", [](auto& c) { c.projector_width = 0; }));
  // Valid geometry but duplicate words: refused by the word table.
  PatternConfig c;
  c.rows = 19;
  c.primitive_height = 5;
  c.gap_y = 2;
  EXPECT_EQ(validationError(c), "");
  EXPECT_THROW(Pattern{ c }, std::invalid_argument);
}

// primitive_width 2147483647 with gap_x 1 wrapped the cell width to a negative number, passed
// validation and made the decoder allocate a 77 GB template.
TEST(Pattern, HugePrimitivesAndGapsAreRefusedWithoutOverflow)
{
  EXPECT_TRUE(refusedNaming<PatternConfig>("primitive_width",
                                           [](auto& c)
                                           {
                                             c.primitive_width = 2147483647;
                                             c.gap_x = 1;
                                           }));
  EXPECT_TRUE(refusedNaming<PatternConfig>("gap_x", [](auto& c) { c.gap_x = 2147483647; }));
  EXPECT_TRUE(refusedNaming<PatternConfig>("primitive_height",
                                           [](auto& c)
                                           {
                                             c.primitive_height = 2147483647;
                                             c.gap_y = 2147483647;
                                           }));
  EXPECT_TRUE(refusedNaming<PatternConfig>("offset_y", [](auto& c) { c.offset_y = 2147483647; }));
  EXPECT_TRUE(refusedNaming<PatternConfig>("projector_width", [](auto& c) { c.projector_width = kMaxImageSide + 1; }));
  // A primitive as wide as the frame is refused by the layout, not by the bound.
  EXPECT_TRUE(refusedNaming<PatternConfig>("cols", [](auto& c) { c.primitive_width = c.projector_width; }));
}
