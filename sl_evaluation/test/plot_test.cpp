// The line chart (plot.h): where points land and in which colour, broken lines at missing data, bad
// charts and paths refused naming the field or file; and sl_eval --plot run as a process.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "sl_evaluation/plot.h"
#include "sl_testing/process.h"

using namespace sl_evaluation;

namespace
{
const double kNan = std::numeric_limits<double>::quiet_NaN();
const cv::Scalar kRed(30, 30, 220), kGreen(40, 170, 40);

std::string tempPath(const std::string& name)
{
  return ::testing::TempDir() + "/sl_plot_" + std::to_string(getpid()) + "_" + name;
}

bool exists(const std::string& path)
{
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

cv::Vec3b bgr(const cv::Scalar& c)
{
  return cv::Vec3b(static_cast<uchar>(c[0]), static_cast<uchar>(c[1]), static_cast<uchar>(c[2]));
}

/// Pixels of exactly colour @p c inside @p area.
int countColour(const cv::Mat& image, const cv::Rect& area, const cv::Scalar& c)
{
  int n = 0;
  for (int y = area.y; y < area.y + area.height; ++y)
    for (int x = area.x; x < area.x + area.width; ++x)
      n += image.at<cv::Vec3b>(y, x) == bgr(c);
  return n;
}

/// Two panels over x in [0, 10]: red points (2, 40) and (8, 90) on top, green (5, -2.5) below.
Chart twoPanels()
{
  Chart c;
  c.title = "test chart";
  c.x = ChartAxis{ "x (m)", 0.0, 10.0, 2.0 };
  c.panels.resize(2);
  c.panels[0].y = ChartAxis{ "valid (%)", 0.0, 100.0, 20.0 };
  c.panels[0].series = { ChartSeries{ "red", { { 2.0, 40.0 }, { 8.0, 90.0 } }, kRed } };
  c.panels[1].y = ChartAxis{ "error (mm)", -5.0, 5.0, 0.0 };
  c.panels[1].series = { ChartSeries{ "green", { { 5.0, -2.5 } }, kGreen } };
  return c;
}

/// Expects std::invalid_argument whose message starts with @p field.
void expectRefused(const Chart& chart, const std::string& field)
{
  try
  {
    renderChart(chart);
    ADD_FAILURE() << "accepted a chart with a bad " << field;
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind(field, 0), 0u) << e.what();
  }
}
}  // namespace

TEST(Plot, PointsLandOnTheirPixelsInTheirColour)
{
  const Chart chart = twoPanels();
  const cv::Rect top = chartPlotArea(chart, 0), bottom = chartPlotArea(chart, 1);
  EXPECT_TRUE((cv::Rect(0, 0, chart.width, chart.height) & top) == top);
  EXPECT_TRUE((cv::Rect(0, 0, chart.width, chart.height) & bottom) == bottom);
  EXPECT_LT(top.y + top.height, bottom.y);  // stacked, top first
  // The axis ends are the plot area's border pixels; x grows right, y up.
  EXPECT_EQ(chartPixel(chart, 0, 0.0, 0.0), cv::Point(top.x, top.y + top.height - 1));
  EXPECT_EQ(chartPixel(chart, 0, 10.0, 100.0), cv::Point(top.x + top.width - 1, top.y));
  const cv::Point a = chartPixel(chart, 0, 2.0, 40.0);
  EXPECT_EQ(a.x, static_cast<int>(std::lround(top.x + 0.2 * (top.width - 1))));
  EXPECT_EQ(a.y, static_cast<int>(std::lround(top.y + top.height - 1 - 0.4 * (top.height - 1))));
  const cv::Point b = chartPixel(chart, 0, 8.0, 90.0);
  const cv::Point g = chartPixel(chart, 1, 5.0, -2.5);
  EXPECT_EQ(g.y, static_cast<int>(std::lround(bottom.y + 0.75 * (bottom.height - 1))));

  const cv::Mat image = renderChart(chart);
  ASSERT_EQ(image.size(), cv::Size(chart.width, chart.height));
  ASSERT_EQ(image.type(), CV_8UC3);
  EXPECT_EQ(image.at<cv::Vec3b>(a), bgr(kRed));
  EXPECT_EQ(image.at<cv::Vec3b>(b), bgr(kRed));
  EXPECT_EQ(image.at<cv::Vec3b>(g), bgr(kGreen));
  // The line joins them: the pixel halfway is (nearly) red; the mirror images of the points are not.
  const cv::Vec3b mid = image.at<cv::Vec3b>((a + b) / 2);
  EXPECT_LT(cv::norm(cv::Vec3d(mid) - cv::Vec3d(bgr(kRed))), 60.0) << mid;
  EXPECT_NE(image.at<cv::Vec3b>(chartPixel(chart, 0, 2.0, 60.0)), bgr(kRed));
  EXPECT_NE(image.at<cv::Vec3b>(chartPixel(chart, 1, 5.0, 2.5)), bgr(kGreen));
  // Each colour stays in its panel (and its legend, right of the plot areas).
  EXPECT_EQ(countColour(image, bottom, kRed), 0);
  EXPECT_EQ(countColour(image, top, kGreen), 0);
  EXPECT_GT(countColour(image, cv::Rect(top.x + top.width, top.y, chart.width - top.x - top.width, top.height), kRed),
            0);

  // Written as PNG and read back: same size, same pixels.
  const std::string path = tempPath("chart.png");
  writeChart(chart, path);
  const cv::Mat back = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(back.size(), cv::Size(900, 700));
  EXPECT_EQ(back.at<cv::Vec3b>(a), bgr(kRed));
  EXPECT_EQ(cv::norm(back, image, cv::NORM_INF), 0.0);
  std::remove(path.c_str());
}

TEST(Plot, MissingDataBreaksTheLineAndAnEmptySeriesLeavesABlankPanel)
{
  Chart chart = twoPanels();
  chart.panels[0].series[0].points = {
    { 2.0, 40.0 }, { 4.0, kNan }, { 6.0, 60.0 }, { kNan, 10.0 }, { 8.0, std::numeric_limits<double>::infinity() }
  };
  chart.panels[1].series[0].points.clear();
  const cv::Mat image = renderChart(chart);
  const cv::Point a = chartPixel(chart, 0, 2.0, 40.0), b = chartPixel(chart, 0, 6.0, 60.0);
  EXPECT_EQ(image.at<cv::Vec3b>(a), bgr(kRed));
  EXPECT_EQ(image.at<cv::Vec3b>(b), bgr(kRed));
  // No line across the missing point between them.
  const cv::Vec3b mid = image.at<cv::Vec3b>((a + b) / 2);
  EXPECT_GT(cv::norm(cv::Vec3d(mid) - cv::Vec3d(bgr(kRed))), 100.0) << mid;
  // Two markers of radius 4 and nothing else in red on the top panel (about 49 px each).
  const int red = countColour(image, chartPlotArea(chart, 0), kRed);
  EXPECT_GE(red, 2 * 40);
  EXPECT_LE(red, 2 * 60);
  EXPECT_EQ(countColour(image, chartPlotArea(chart, 1), kGreen), 0);

  // Only missing data: blank panels, no error.
  chart.panels[0].series[0].points = { { kNan, kNan } };
  const cv::Mat blank = renderChart(chart);
  EXPECT_EQ(countColour(blank, chartPlotArea(chart, 0), kRed), 0);
}

TEST(Plot, PointsOutsideTheAxesAreClipped)
{
  Chart chart = twoPanels();
  chart.panels[0].series[0].points = { { 5.0, 50.0 }, { 5.0, 1e300 } };
  chart.panels[0].series.push_back(ChartSeries{ "outside", { { 20.0, 50.0 } }, kGreen });
  const cv::Mat image = renderChart(chart);
  const cv::Rect top = chartPlotArea(chart, 0);
  EXPECT_EQ(image.at<cv::Vec3b>(chartPixel(chart, 0, 5.0, 50.0)), bgr(kRed));
  // The line towards the far point runs up to the frame and stops there: nothing red above it.
  const cv::Vec3b on_line = image.at<cv::Vec3b>(chartPixel(chart, 0, 5.0, 75.0));
  EXPECT_LT(cv::norm(cv::Vec3d(on_line) - cv::Vec3d(bgr(kRed))), 60.0) << on_line;
  EXPECT_EQ(countColour(image, cv::Rect(0, 0, chart.width, top.y), kRed), 0);
  // A point right of the x axis: no marker in the plot area.
  EXPECT_EQ(countColour(image, top, kGreen), 0);
}

TEST(Plot, BadChartsAreRefusedNamingTheField)
{
  Chart c = twoPanels();
  c.width = 100;
  expectRefused(c, "width");
  c = twoPanels();
  c.height = 250;
  expectRefused(c, "height");
  c = twoPanels();
  c.panels.clear();
  expectRefused(c, "panels");
  c = twoPanels();
  c.x.max = c.x.min;
  expectRefused(c, "x.max");
  c = twoPanels();
  c.x.min = kNan;
  expectRefused(c, "x.min");
  c = twoPanels();
  c.x.tick = 0.01;
  expectRefused(c, "x.tick");
  c = twoPanels();
  c.panels[1].y.tick = -1.0;
  expectRefused(c, "panels[1].y.tick");
  c = twoPanels();
  c.panels[0].y.max = std::numeric_limits<double>::infinity();
  expectRefused(c, "panels[0].y.max");
  EXPECT_THROW(chartPixel(twoPanels(), 2, 0.0, 0.0), std::invalid_argument);
}

TEST(Plot, UnwritablePathsAreRefusedNamingTheFile)
{
  const Chart chart = twoPanels();
  const std::string missing_dir = tempPath("no_such_dir") + "/chart.png";
  try
  {
    writeChart(chart, missing_dir);
    ADD_FAILURE() << "wrote into a missing directory";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find(missing_dir), std::string::npos) << e.what();
  }
  const std::string dir = tempPath("dir.png");
  ASSERT_EQ(mkdir(dir.c_str(), 0755), 0);
  try
  {
    checkChartPath(dir);
    ADD_FAILURE() << "accepted a directory";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find(dir + ": it is a directory"), std::string::npos) << e.what();
  }
  rmdir(dir.c_str());
  const std::string jpg = tempPath("chart.jpg");
  try
  {
    writeChart(chart, jpg);
    ADD_FAILURE() << "accepted a .jpg";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find(jpg), std::string::npos) << e.what();
  }
  EXPECT_FALSE(exists(jpg));
  EXPECT_NO_THROW(checkChartPath(tempPath("new.PNG")));
  EXPECT_FALSE(exists(tempPath("new.PNG")));  // checked, not created
}

TEST(Plot, AxesFitTheirValues)
{
  EXPECT_DOUBLE_EQ(niceTick(0.0, 100.0), 20.0);
  EXPECT_DOUBLE_EQ(niceTick(0.35, 0.95), 0.1);
  EXPECT_DOUBLE_EQ(niceTick(0.0, 3.3), 0.5);
  EXPECT_THROW(niceTick(1.0, 1.0), std::invalid_argument);
  ChartAxis a = fitAxis("d", { 0.95, 0.35, kNan }, false);
  EXPECT_NEAR(a.min, 0.3, 1e-12);
  EXPECT_NEAR(a.max, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(a.tick, 0.1);
  EXPECT_EQ(a.label, "d");
  a = fitAxis("e", { 3.3, 0.2 }, true);
  EXPECT_EQ(a.min, 0.0);
  EXPECT_DOUBLE_EQ(a.max, 3.5);
  a = fitAxis("one", { 0.45 }, false);  // a range around a single value
  EXPECT_NEAR(a.min, 0.40, 1e-12);
  EXPECT_NEAR(a.max, 0.50, 1e-12);
  a = fitAxis("none", { kNan }, true);
  EXPECT_EQ(a.min, 0.0);
  EXPECT_EQ(a.max, 1.0);
  a = fitAxis("zeros", { 0.0, 0.0 }, true);
  EXPECT_EQ(a.min, 0.0);
  EXPECT_GT(a.max, 0.0);
}

TEST(EvalStats, ErrorPercentileIsTheNearestRank)
{
  EvalStats s, t;
  for (int mm = 100; mm >= 51; --mm)
    s.abs_errors.push_back(static_cast<float>(mm / 1000.0));
  for (int mm = 1; mm <= 50; ++mm)
    t.abs_errors.push_back(static_cast<float>(mm / 1000.0));
  s.add(t);
  ASSERT_EQ(s.abs_errors.size(), 100u);
  EXPECT_NEAR(s.errorPercentileMm(50.0), 50.0, 1e-4);
  EXPECT_NEAR(s.errorPercentileMm(95.0), 95.0, 1e-4);
  EXPECT_NEAR(s.errorPercentileMm(100.0), 100.0, 1e-4);
  EXPECT_NEAR(s.errorPercentileMm(0.5), 1.0, 1e-4);
  EXPECT_THROW(s.errorPercentileMm(0.0), std::invalid_argument);
  EXPECT_THROW(s.errorPercentileMm(101.0), std::invalid_argument);
  EXPECT_EQ(EvalStats().errorPercentileMm(95.0), 0.0);
}

TEST(Plot, DecodingChartPutsDistancesInOrder)
{
  DistanceResult far, near, blind;
  far.distance = 0.9;
  far.stats.visible = 200;
  far.stats.valid_visible = 150;
  far.stats.with_depth = 4;
  far.stats.sum_abs_error = 0.004;
  far.stats.max_abs_error = 0.003;
  far.stats.abs_errors = { 0.0005f, 0.0005f, 0.0003f, 0.003f };
  near.distance = 0.4;
  near.stats.visible = 100;
  near.stats.valid_visible = 100;
  blind.distance = 0.6;  // nothing visible, no depth
  const Chart c = decodingChart({ far, near, blind }, "t");
  ASSERT_EQ(c.panels.size(), 2u);
  const std::vector<cv::Point2d>& valid = c.panels[0].series.at(0).points;
  ASSERT_EQ(valid.size(), 3u);
  EXPECT_EQ(valid[0], cv::Point2d(0.4, 100.0));
  EXPECT_TRUE(std::isnan(valid[1].y));
  EXPECT_EQ(valid[2], cv::Point2d(0.9, 75.0));
  ASSERT_EQ(c.panels[1].series.size(), 3u);                    // mean, 95th percentile, max
  EXPECT_TRUE(std::isnan(c.panels[1].series[0].points[0].y));  // 0.4 m: no depth
  EXPECT_NEAR(c.panels[1].series[0].points[2].y, 1.0, 1e-9);
  EXPECT_NEAR(c.panels[1].series[1].points[2].y, 3.0, 1e-4);
  EXPECT_NEAR(c.panels[1].series[2].points[2].y, 3.0, 1e-9);
  EXPECT_LE(c.x.min, 0.4);
  EXPECT_GE(c.x.max, 0.9);
  EXPECT_GE(c.panels[1].y.max, 3.0);
  EXPECT_EQ(c.panels[0].y.max, 100.0);
  EXPECT_NO_THROW(renderChart(c));
}

TEST(SlEval, PlotOptionRefusesBadFilesBeforeTheRun)
{
  const std::string bin = SL_EVAL_BIN;
  std::string out;
  EXPECT_EQ(sl_testing::run(bin + " --plane 0.7 --plot", out), 2);
  EXPECT_NE(out.find("--plot needs a value"), std::string::npos) << out;
  out.clear();
  const std::string missing = tempPath("no_such_dir") + "/eval.png";
  EXPECT_EQ(sl_testing::run(bin + " --plane 0.7 --plot " + missing, out), 2);
  EXPECT_NE(out.find("--plot: cannot write " + missing), std::string::npos) << out;
  EXPECT_EQ(out.find("scene 1 of"), std::string::npos) << "evaluated before refusing: " << out;
  out.clear();
  EXPECT_EQ(sl_testing::run(bin + " --plane 0.7 --plot " + tempPath("eval.jpg"), out), 2);
  EXPECT_NE(out.find("--plot: the chart's file name must end in .png"), std::string::npos) << out;
  out.clear();
  const std::string cylinder = findScene({ "cylinder_plane" });
  EXPECT_EQ(sl_testing::run(bin + " " + cylinder + " --plot " + tempPath("eval.png"), out), 2);
  EXPECT_NE(out.find("--plot: no plane at a known distance"), std::string::npos) << out;
  EXPECT_FALSE(exists(tempPath("eval.png")));
}

TEST(SlEval, PlotsValidPercentAndErrorAgainstDistance)
{
  const std::string path = tempPath("eval.png");
  std::string out;
  ASSERT_EQ(sl_testing::run(std::string(SL_EVAL_BIN) + " --frames 1 --plane 0.7 --plane 0.5 --plot " + path, out), 0)
      << out;
  // A progress line per plane; the table as before.
  EXPECT_NE(out.find("scene 1 of 2: near_plane_700 (0.70 m), seed 1000, triangulation ... done"), std::string::npos)
      << out;
  EXPECT_NE(out.find("scene 2 of 2: near_plane_500 (0.50 m)"), std::string::npos) << out;
  EXPECT_NE(out.find("all scenes (triangulation): 2 frames"), std::string::npos) << out;
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty()) << out;

  // The same evaluation in this process gives the chart the tool drew: its points are in the PNG.
  const sl_projector::Rig rig = sl_projector::loadRig(defaultRigFile());
  std::vector<DistanceResult> results;
  for (double d : { 0.7, 0.5 })
    results.push_back(
        DistanceResult{ d, evaluateScene(rig, planeScene(rig, d), "p", sl_decoder::DecoderConfig(), 1).stats });
  const Chart chart = decodingChart(results, "");
  ASSERT_EQ(image.size(), cv::Size(chart.width, chart.height));
  for (size_t k = 0; k < 2; ++k)
  {
    const ChartSeries& valid = chart.panels[0].series[0];
    const ChartSeries& max = chart.panels[1].series.back();
    EXPECT_EQ(image.at<cv::Vec3b>(chartPixel(chart, 0, valid.points[k].x, valid.points[k].y)), bgr(valid.colour))
        << "valid % at " << valid.points[k];
    EXPECT_EQ(image.at<cv::Vec3b>(chartPixel(chart, 1, max.points[k].x, max.points[k].y)), bgr(max.colour))
        << "max error at " << max.points[k];
  }
  std::remove(path.c_str());
}

// sl_eval for another rig file: the near rows and the far planes, with the decode time; a defocus
// scale out of range is refused naming the option, before the run.
TEST(SlEval, PrintsTheNearAndFarRowsForARigFile)
{
  const std::string bin = SL_EVAL_BIN;
  const std::string rig = std::string(SL_EVALUATION_TEST_DIR) + "/rigs/left_rig.yaml";
  std::string out;
  ASSERT_EQ(sl_testing::run(bin + " --rig " + rig + " --near-far --defocus-scale 1.2 --frames 1", out), 0) << out;
  EXPECT_NE(out.find("dec_ms"), std::string::npos) << out;
  for (const char* row : { "near_plane_350 ", "near_plane_400 ", "near_plane_450 ", "near_plane_550 ",
                           "near_plane_700 ", "near_plane_900 ", "near_plane_1200 " })
    EXPECT_NE(out.find(row), std::string::npos) << row << " missing in\n" << out;
  EXPECT_NE(out.find("all scenes (triangulation): 7 frames"), std::string::npos) << out;
  // Each row ends in the decode time: ten columns, the last a positive number of ms.
  const size_t at = out.find("\nnear_plane_400 ");  // the row, not the progress line
  ASSERT_NE(at, std::string::npos);
  std::istringstream row(out.substr(at + 1, out.find('\n', at + 1) - at - 1));
  std::vector<std::string> columns;
  for (std::string c; row >> c;)
    columns.push_back(c);
  ASSERT_EQ(columns.size(), 10u) << out;
  EXPECT_GT(std::stod(columns.back()), 0.0) << out;
  EXPECT_EQ(std::stoi(columns[5]), 0) << "wrong correspondences: " << out;

  out.clear();
  EXPECT_EQ(sl_testing::run(bin + " --rig " + rig + " --near-far --defocus-scale 5", out), 2);
  EXPECT_NE(out.find("--defocus-scale: must be 0.1 to 4"), std::string::npos) << out;
  EXPECT_EQ(out.find("scene 1 of"), std::string::npos) << out;
  out.clear();
  EXPECT_EQ(sl_testing::run(bin + " --rig /no/such/rig.yaml --plane 0.7", out), 2);
  EXPECT_NE(out.find("/no/such/rig.yaml"), std::string::npos) << out;
}
