// Residual plots: the picture's size, arrows where a known residual puts them, the column residuals
// of the plane calibration and the corner residuals of the full calibration on synthetic data, the
// errors for nothing to plot and unwritable files, and the tools' bad --residuals arguments.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>

#include <unistd.h>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include "sl_calibration/residual_plot.h"
#include "sl_testing/process.h"
#include "test_rig.h"

using namespace sl_calibration;

namespace
{
std::string tempPath(const std::string& name)
{
  return ::testing::TempDir() + "/sl_calibration_" + std::to_string(getpid()) + "_" + name;
}

ImageResidual residual(double u, double v, double du, double dv, int view = 0)
{
  ImageResidual r;
  r.pixel = Eigen::Vector2d(u, v);
  r.residual = Eigen::Vector2d(du, dv);
  r.view = view;
  return r;
}

ResidualPlotOptions cameraOptions()
{
  ResidualPlotOptions o;
  o.image_size = cv::Size(752, 480);
  o.title = "test";
  return o;
}

/// Whether a pixel within 1 px of @p p has about @p colour (BGR).
bool colourNear(const cv::Mat& img, const cv::Point2d& p, const cv::Vec3b& colour)
{
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
    {
      const cv::Vec3b c =
          img.at<cv::Vec3b>(static_cast<int>(std::lround(p.y)) + dy, static_cast<int>(std::lround(p.x)) + dx);
      if (std::abs(c[0] - colour[0]) < 40 && std::abs(c[1] - colour[1]) < 40 && std::abs(c[2] - colour[2]) < 40)
        return true;
    }
  return false;
}

/// Whether every pixel within 2 px of @p p is the image area's background.
bool blank(const cv::Mat& img, const cv::Point2d& p)
{
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx)
      if (img.at<cv::Vec3b>(static_cast<int>(std::lround(p.y)) + dy, static_cast<int>(std::lround(p.x)) + dx) !=
          cv::Vec3b(248, 248, 248))
        return false;
  return true;
}

std::string errorOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const CalibrationError& e)
  {
    return e.what();
  }
  return "";
}

const cv::Vec3b kView0(180, 119, 31), kView1(14, 127, 255);  // the first two colours of the palette
}  // namespace

TEST(ResidualPlot, FileHasTheExpectedSize)
{
  const std::string path = tempPath("residuals.png");
  std::remove(path.c_str());
  writeResidualPlot(path, { residual(100, 100, 0.1, 0.0), residual(600, 400, 0.0, 0.2, 1) }, cameraOptions());
  const cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty()) << path;
  ResidualPlotLayout l;
  drawResidualPlot({ residual(100, 100, 0.1, 0.0), residual(600, 400, 0.0, 0.2, 1) }, cameraOptions(), &l);
  EXPECT_EQ(img.cols, 1000);
  EXPECT_EQ(img.size(), l.size);
  // The 752 x 480 image scaled to the 960 px between the margins, title above, legend below.
  EXPECT_EQ(l.image_area.width, 960);
  EXPECT_EQ(l.image_area.height, 613);
  EXPECT_GT(l.image_area.y, 30);
  EXPECT_GT(img.rows, l.image_area.br().y + 40);
  std::remove(path.c_str());
}

TEST(ResidualPlot, ArrowsWhereTheResidualsPointThem)
{
  ResidualPlotOptions o = cameraOptions();
  o.magnification = 40.0;
  // View 0: 0.5 px to the right; view 1: 0.5 px up. At x40 each arrow is 20 image px long.
  const std::vector<ImageResidual> r{ residual(200, 150, 0.5, 0.0, 0), residual(500, 300, 0.0, -0.5, 1) };
  ResidualPlotLayout l;
  const cv::Mat img = drawResidualPlot(r, o, &l);
  EXPECT_DOUBLE_EQ(l.magnification, 40.0);
  const double half = 0.5 * 20.0 * l.scale;  // half the arrow in the picture
  const cv::Point2d a = l.toPicture(Eigen::Vector2d(200, 150)), b = l.toPicture(Eigen::Vector2d(500, 300));
  EXPECT_NEAR(a.x, 20 + 200.5 * 960.0 / 752.0, 1e-9);
  EXPECT_TRUE(colourNear(img, a, kView0)) << "the dot";
  EXPECT_TRUE(colourNear(img, a + cv::Point2d(half, 0), kView0)) << "the arrow's middle";
  EXPECT_TRUE(colourNear(img, a + cv::Point2d(2 * half - 2, 0), kView0)) << "near the arrow's tip";
  EXPECT_TRUE(blank(img, a - cv::Point2d(half, 0)));
  EXPECT_TRUE(blank(img, a + cv::Point2d(0, half)));
  EXPECT_TRUE(blank(img, a + cv::Point2d(2 * half + 6, 0))) << "no longer than the residual";
  EXPECT_TRUE(colourNear(img, b + cv::Point2d(0, -half), kView1));
  EXPECT_TRUE(blank(img, b + cv::Point2d(half, 0)));
  EXPECT_TRUE(blank(img, b + cv::Point2d(0, half)));
}

TEST(ResidualPlot, AutomaticMagnificationAndScaleBar)
{
  std::vector<ImageResidual> r;
  for (int i = 0; i < 100; ++i)
    r.push_back(residual(10 + 7 * i, 240, 0.1, 0.0));
  ResidualPlotLayout l;
  drawResidualPlot(r, cameraOptions(), &l);
  // 0.1 px drawn about 30 picture px long at 1.277 picture px per image px: x235, the 1-2-5 step below.
  EXPECT_DOUBLE_EQ(l.magnification, 200.0);
  EXPECT_NEAR(l.scale_bar_residual, 0.2, 1e-12);
  EXPECT_EQ(l.scale_bar_length, static_cast<int>(std::lround(0.2 * 200.0 * 960.0 / 752.0)));
  const ResidualStatistics s = residualStatistics({ residual(0, 0, 3, 4), residual(1, 1, 0, 0) });
  EXPECT_EQ(s.points, 2u);
  EXPECT_DOUBLE_EQ(s.max, 5.0);
  EXPECT_NEAR(s.rms, std::sqrt(12.5), 1e-12);
}

TEST(ResidualPlot, ColourByMagnitude)
{
  ResidualPlotOptions o = cameraOptions();
  o.colouring = ResidualColouring::ByMagnitude;
  o.magnification = 10.0;
  ResidualPlotLayout l;
  const cv::Mat img = drawResidualPlot({ residual(100, 100, 0.01, 0.0), residual(500, 300, 2.0, 0.0) }, o, &l);
  const cv::Vec3b small = img.at<cv::Vec3b>(l.toPicture(Eigen::Vector2d(100, 100)));
  const cv::Vec3b large = img.at<cv::Vec3b>(l.toPicture(Eigen::Vector2d(500, 300)));
  EXPECT_GT(small[0], 200);  // blue
  EXPECT_LT(small[2], 50);
  EXPECT_GT(large[2], 200);  // red
  EXPECT_LT(large[0], 50);
}

TEST(ResidualPlot, ErrorsNameTheFile)
{
  const ResidualPlotOptions o = cameraOptions();
  const std::string path = tempPath("empty.png");
  std::string m = errorOf([&] { writeResidualPlot(path, {}, o); });
  EXPECT_NE(m.find(path + ": no residuals to plot"), std::string::npos) << m;
  m = errorOf([&] { writeResidualPlot(path, { residual(1, 1, std::nan(""), 0) }, o); });
  EXPECT_NE(m.find(path + ": no residuals to plot"), std::string::npos) << m;
  const std::string nowhere = "/nonexistent_sl_calibration_dir/r.png";
  m = errorOf([&] { writeResidualPlot(nowhere, { residual(1, 1, 0.1, 0) }, o); });
  EXPECT_NE(m.find(nowhere + ": cannot write the residual plot"), std::string::npos) << m;
  m = errorOf([&] { writeResidualPlot(tempPath("r.jpg"), { residual(1, 1, 0.1, 0) }, o); });
  EXPECT_NE(m.find("r.jpg: a residual plot is written as PNG"), std::string::npos) << m;
  ResidualPlotOptions bad = o;
  bad.image_size = cv::Size(0, 480);
  m = errorOf([&] { writeResidualPlot(path, { residual(1, 1, 0.1, 0) }, bad); });
  EXPECT_NE(m.find(path + ": image_size"), std::string::npos) << m;
  m = errorOf([&] { writeCameraResidualPlot(path, FullCalibrationResult()); });
  EXPECT_NE(m.find(path + ": no board corners to plot"), std::string::npos) << m;
  EXPECT_TRUE(isPngPath("a/B.PNG"));
  EXPECT_FALSE(isPngPath("a.png.csv"));
}

// Column residuals: a primitive on the exact curve has none; one seen 0.3 px off at one distance
// has its largest residual there, pointing back (left), and its depth residual is the column
// residual times the model's slope.
TEST(ResidualPlot, PlaneColumnResiduals)
{
  PlaneCalibrationOptions options;
  options.normal = PlaneNormal::Camera;  // the target depth is the distance itself
  PlaneCalibration cal(trueRig(), options);
  const double distances[5] = { 0.5, 0.6, 0.7, 0.8, 0.9 };
  for (int k = 0; k < 5; ++k)
  {
    const double u = 300.0 + 80.0 / distances[k];
    cal.addSamples(distances[k], { { 0, 0, u, 200.0 }, { 0, 1, u + (k == 2 ? 0.3 : 0.0), 210.0 } }, "synthetic");
  }
  const PlaneCalibrationResult res = cal.fit();
  const std::vector<ImageResidual> r = res.columnResiduals();
  ASSERT_EQ(r.size(), 10u);
  const ImageResidual* off = nullptr;
  double largest = 0.0;
  for (const ImageResidual& x : r)
  {
    EXPECT_EQ(x.residual.y(), 0.0);
    if (x.pixel.y() == 200.0)
      EXPECT_LT(x.residual.norm(), 1e-6) << "exact primitive at view " << x.view;
    else if (x.residual.norm() > largest)
    {
      largest = x.residual.norm();
      off = &x;
    }
  }
  ASSERT_NE(off, nullptr);
  EXPECT_EQ(off->view, 2);
  EXPECT_NEAR(off->pixel.x(), 300.0 + 80.0 / 0.7 + 0.3, 1e-9);
  std::cout << "column residual of the primitive seen 0.3 px off: " << off->residual.x() << " px\n";
  EXPECT_LT(off->residual.x(), -0.1);  // measured -0.154 px: the fit takes up half of it
  const sl_projector::DepthModel& m = res.primitives[1].rational;
  const double u = off->pixel.x(), slope = (m.b - m.a * m.c) / ((1.0 + m.c * u) * (1.0 + m.c * u));
  EXPECT_NEAR(res.primitives[1].rational_residual[2], -slope * off->residual.x(),
              0.05 * std::abs(res.primitives[1].rational_residual[2]));
  const std::string path = tempPath("plane_residuals.png");
  writePlaneResidualPlot(path, res, cv::Size(752, 480));
  EXPECT_EQ(cv::imread(path).cols, 1000);
  std::remove(path.c_str());
}

// Corner residuals of a full calibration on synthetic views (exact corners of the true camera, one
// corner 0.8 px off) and known-distance planes: one per corner, the displaced corner's the largest
// and pointing back, their rms the camera's reported rms.
TEST(ResidualPlot, FullCalibrationCornerResiduals)
{
  const sl_projector::Rig& rig = trueRig();
  const Board board = parseBoardSize("9x6", 0.022);
  FullCalibrationOptions options;
  options.joint_refinement = false;
  FullCalibration cal(rig, board, options);
  const std::vector<cv::Point3f> object = board.objectPoints();
  const Eigen::Vector3d centre(4 * 0.022, 2.5 * 0.022, 0.0);
  const double tilts[5][2] = { { 0.35, 0.0 }, { -0.35, 0.1 }, { 0.0, 0.35 }, { 0.1, -0.35 }, { 0.2, 0.2 } };
  for (int j = 0; j < 5; ++j)
  {
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(tilts[j][0], Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(tilts[j][1], Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const Eigen::Vector3d t = Eigen::Vector3d(0.0, 0.0, 0.6) - R * centre;
    std::vector<cv::Point2f> corners;
    for (const cv::Point3f& p : object)
    {
      const Eigen::Vector2d px = rig.camera.project(R * Eigen::Vector3d(p.x, p.y, p.z) + t);
      corners.emplace_back(static_cast<float>(px.x()), static_cast<float>(px.y()));
    }
    if (j == 2)
      corners[20].x += 0.8f;
    cal.addCameraCorners("board_" + std::to_string(j) + ".png", corners);
  }
  const sl_projector::Pattern pattern(rig.pattern);
  for (double d : { 0.5, 0.6, 0.7 })
  {
    const CalibrationPlane plane = planeAtDistance(rig, d, PlaneCalibrationOptions());
    std::vector<PrimitiveSample> samples;
    for (int row = 0; row < rig.pattern.rows; ++row)
      for (int col = 0; col < rig.pattern.cols; ++col)
      {
        const cv::Point2d q = pattern.primitiveCentroid(row, col);
        Eigen::Vector3d o, dir;
        rig.projectorRay(Eigen::Vector2d(q.x, q.y), o, dir);
        const Eigen::Vector2d px =
            rig.camera.project(o + (plane.offset - plane.normal.dot(o)) / plane.normal.dot(dir) * dir);
        if (rig.camera.inImage(px))
          samples.push_back(PrimitiveSample{ row, col, px.x(), px.y() });
      }
    cal.addDistanceSamples("plane_" + std::to_string(d), d, samples);
  }
  const FullCalibrationResult res = cal.calibrate();
  ASSERT_EQ(res.camera_residuals.size(), 5u * object.size());
  const ImageResidual* largest = &res.camera_residuals.front();
  double sum2 = 0.0;
  for (const ImageResidual& r : res.camera_residuals)
  {
    sum2 += r.residual.squaredNorm();
    if (r.residual.norm() > largest->residual.norm())
      largest = &r;
  }
  EXPECT_EQ(largest->view, 2);
  EXPECT_EQ(res.camera_views[2], "board_2.png");
  EXPECT_EQ(largest - &res.camera_residuals.front(), static_cast<long>(2 * object.size() + 20));
  std::cout << "residual of the corner 0.8 px off: " << largest->residual.transpose() << " px\n";
  EXPECT_LT(largest->residual.x(), -0.5) << "points back to where the corner belongs";  // measured -0.764 px
  EXPECT_NEAR(std::sqrt(sum2 / res.camera_residuals.size()), res.camera.rms, 1e-3);
  const std::string path = tempPath("camera_residuals.png");
  writeCameraResidualPlot(path, res);
  EXPECT_EQ(cv::imread(path).cols, 1000);
  std::remove(path.c_str());
}

// The tools refuse a --residuals without a file name, with another option in its place, or where
// nothing can be written, naming the option and the file, with exit status 2 (bad arguments).
TEST(ResidualPlot, ToolsRefuseBadResidualsArguments)
{
  const std::string full = std::string(SL_CALIBRATE_FULL_BIN) + " --rig r.yaml --out o.yaml --board 9x6 --square 0.022";
  const std::string plane = std::string(SL_CALIBRATE_PLANE_BIN) + " --rig r.yaml --out o.yaml a.png:0.5";
  const std::string nowhere = "/nonexistent_sl_calibration_dir/r.png";
  const struct
  {
    std::string command, message;
  } cases[] = {
    { full + " --camera-view b.png --residuals", "--residuals needs a value" },
    { full + " --camera-view b.png --residuals --k3", "--residuals needs a file name, got '--k3'" },
    { full + " --camera-view b.png --residuals " + nowhere,
      "--residuals " + nowhere + ": cannot write there (/nonexistent_sl_calibration_dir does not exist" },
    { full + " --camera-view b.png --residuals /tmp/r.jpg", "--residuals /tmp/r.jpg: the file name must end in .png" },
    { full + " --camera-info c.yaml --plane p.png:0.5 --residuals /tmp/r.png",
      "--residuals /tmp/r.png: the camera's residuals need board images" },
    { plane + " --residuals", "--residuals needs a value" },
    { plane + " --residuals " + nowhere, "--residuals " + nowhere + ": cannot write there" },
    { plane + " --residuals /tmp/a.png --residuals /tmp/b.png",
      "--residuals /tmp/b.png: a picture is asked for already (/tmp/a.png)" },
  };
  for (const auto& c : cases)
  {
    std::string output;
    EXPECT_EQ(sl_testing::run(c.command, output), 2) << c.command << "\n" << output;
    EXPECT_NE(output.find(c.message), std::string::npos) << c.command << "\n" << output;
  }
}
