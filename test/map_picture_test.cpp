// The exploration picture (map_picture.h): grids merged into one map, and where its cells, the path
// and the scale bar land in the image.
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "map_picture.h"

namespace sl_bringup_test
{
namespace
{
/// A @p n x @p n grid of 0.1 m cells, every cell @p value.
std::vector<std::int8_t> filled(int n, std::int8_t value)
{
  return std::vector<std::int8_t>(static_cast<std::size_t>(n * n), value);
}

TEST(ExploredMap, KnownCellsReplaceAndUnknownKeep)
{
  ExploredMap map;
  EXPECT_EQ(map.at(0.0, 0.0), -1);
  EXPECT_TRUE(map.knownBox().empty());
  map.merge(0.0, 0.0, 0.1, 4, 4, filled(4, 0));
  EXPECT_EQ(map.at(0.05, 0.35), 0);
  EXPECT_EQ(map.at(0.45, 0.05), -1) << "outside the grid";
  // A window moved by (0.2, 0.1): unknown everywhere but one occupied cell at (0.3, 0.2).
  std::vector<std::int8_t> moved = filled(4, -1);
  moved[1 * 4 + 1] = 100;
  map.merge(0.2, 0.1, 0.1, 4, 4, moved);
  EXPECT_EQ(map.at(0.35, 0.25), 100);
  EXPECT_EQ(map.at(0.25, 0.25), 0) << "an unknown cell of a newer grid keeps what was known";
  EXPECT_EQ(map.at(0.55, 0.45), -1);
  // Far away, below and left of the first: the map grows.
  map.merge(-5.0, -3.0, 0.1, 4, 4, filled(4, 50));
  EXPECT_EQ(map.at(-4.95, -2.95), 50);
  EXPECT_EQ(map.at(0.35, 0.25), 100);
  const MapBox box = map.knownBox();
  EXPECT_NEAR(box.min_x, -5.0, 1e-9);
  EXPECT_NEAR(box.min_y, -3.0, 1e-9);
  EXPECT_NEAR(box.max_x, 0.4, 1e-9);
  EXPECT_NEAR(box.max_y, 0.4, 1e-9);
}

TEST(ExploredMap, RefusesGridsThatDoNotFit)
{
  ExploredMap map;
  map.merge(0.0, 0.0, 0.1, 2, 2, filled(2, 0));
  auto message = [&](double ox, double res, int w, std::size_t cells)
  {
    try
    {
      map.merge(ox, 0.0, res, w, 2, std::vector<std::int8_t>(cells, 0));
    }
    catch (const std::invalid_argument& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(0.0, 0.1, 2, 3).find("3 cells for 2 x 2"), std::string::npos);
  EXPECT_NE(message(0.0, 0.05, 2, 4).find("resolution"), std::string::npos);
  EXPECT_NE(message(0.0, 0.0, 2, 4).find("not positive"), std::string::npos);
  EXPECT_NE(message(0.03, 0.1, 2, 4).find("origin x"), std::string::npos);
  EXPECT_EQ(map.at(0.05, 0.05), 0) << "a refused grid changes nothing";
}

TEST(SceneOutline, PointsOnTheObjectsInTheMapFrame)
{
  // A wall facing -x at world x = 1 and a box 0.1 m high (below the upper row of rays).
  const sl_sim::Scene scene = sl_sim::parseScene(R"(format_version: 1
objects:
  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], floor: true}
  - {type: plane, name: wall, position: [1.0, 0, 1.0], normal: [-1, 0, 0], size: [4.0, 2.0]}
  - {type: box, name: box, position: [0, -1.0, 0.05], size: [0.4, 0.4, 0.1]}
)");
  // The map's frame at world (0.5, 0.2), turned by 90 degrees: world x is the map's -y.
  const MapFrame frame{ 0.5, 0.2, M_PI / 2.0 };
  const MapPoint w = frame.toWorld(frame.fromWorld(0.3, -0.7));
  EXPECT_NEAR(w.x, 0.3, 1e-12);
  EXPECT_NEAR(w.y, -0.7, 1e-12);
  MapBox box;
  box.add({ -2.0, -1.0 });
  box.add({ 2.0, 1.0 });
  const std::vector<MapPoint> points = sceneOutline(scene, frame, box);
  int on_wall = 0, on_box = 0;
  for (const MapPoint& p : points)
  {
    const MapPoint world = frame.toWorld(p);
    if (std::abs(world.x - 1.0) < 1e-6)
      ++on_wall;
    else if (std::abs(std::abs(world.x) - 0.2) < 1e-6 || std::abs(std::abs(world.y + 1.0) - 0.2) < 1e-6)
      ++on_box;
    else
      ADD_FAILURE() << "a point off the objects at world (" << world.x << ", " << world.y << ")";
  }
  // The wall (world y -2..2: map x -2.2..1.8) across 3.8 m of the box: a point every 2 cm of it
  // (191 columns) at both heights.
  EXPECT_NEAR(on_wall, 2 * 191, 2);
  // The box (0.4 m square) at 0.05 m only: two faces on each of 21 rows and 21 columns.
  EXPECT_NEAR(on_box, 84, 4);
}

TEST(MapPicture, CellsPathAndScaleBarWhereTheyBelong)
{
  ExploredMap map;
  std::vector<std::int8_t> cells = filled(20, 0);  // 2 x 2 m free ...
  for (int col = 0; col < 20; ++col)
    cells[19 * 20 + col] = 100;  // ... with a wall along its top row
  for (int row = 0; row < 10; ++row)
    for (int col = 10; col < 20; ++col)
      cells[row * 20 + col] = -1;  // and its lower right quarter unknown
  map.merge(0.0, 0.0, 0.1, 20, 20, cells);
  MapPictureContent content;
  content.path = { { 0.2, 1.0 }, { 1.0, 1.0 } };
  content.title = { "a title line", "a second one" };
  content.pixels_per_metre = 100.0;
  content.margin = 0.2;
  MapPictureLayout layout;
  const cv::Mat image = drawMapPicture(map, content, &layout);
  ASSERT_EQ(image.type(), CV_8UC3);
  EXPECT_EQ(layout.top, 8 + 2 * 18) << "two title lines";
  EXPECT_EQ(layout.cols, 240) << "2 m and 2 x 0.2 m margin at 100 pixels/m";
  EXPECT_EQ(layout.rows, 240);
  EXPECT_GE(image.cols, 240);
  EXPECT_EQ(image.rows, layout.top + 240 + 44);
  auto at = [&](double x, double y) { return image.at<cv::Vec3b>(layout.pixel({ x, y })); };
  EXPECT_EQ(at(0.5, 0.5), cv::Vec3b(245, 245, 245)) << "free: light";
  EXPECT_EQ(at(1.0, 1.95), cv::Vec3b(45, 45, 45)) << "occupied: dark";
  EXPECT_EQ(at(1.5, 0.5), cv::Vec3b(185, 185, 185)) << "unknown: grey";
  EXPECT_EQ(at(-0.1, -0.1), cv::Vec3b(185, 185, 185)) << "the margin: unknown";
  const cv::Vec3b path = at(0.6, 1.0);
  EXPECT_GT(path[0] + path[2], 200) << "the path: blue to red";
  EXPECT_LT(path[1], 100);
  const cv::Vec3b start = at(0.2, 1.0);
  EXPECT_GT(start[1], 120) << "the start: green";
  EXPECT_LT(start[2], 50);
  const cv::Vec3b end = at(1.0, 1.0);
  EXPECT_GT(end[2], 200) << "the end: red";
  EXPECT_LT(end[1], 50);
  // The scale bar: 100 black pixels (1 m) below the map, from column 10.
  const int bar_row = layout.top + 240 + 14;
  for (int c = 10; c <= 110; ++c)
    ASSERT_EQ(image.at<cv::Vec3b>(bar_row, c), cv::Vec3b(0, 0, 0)) << "column " << c;
  EXPECT_NE(image.at<cv::Vec3b>(bar_row, 5), cv::Vec3b(0, 0, 0));
  EXPECT_NE(image.at<cv::Vec3b>(bar_row, 114), cv::Vec3b(0, 0, 0));
}

TEST(MapPicture, EmptyMapStillDrawsAndScalesToAbout700Pixels)
{
  const cv::Mat nothing = drawMapPicture(ExploredMap(), MapPictureContent());
  EXPECT_FALSE(nothing.empty());
  ExploredMap map;
  map.merge(-2.0, -1.0, 0.1, 40, 20, std::vector<std::int8_t>(800, 0));  // 4 x 2 m
  MapPictureContent content;
  content.margin = 0.5;
  MapPictureLayout layout;
  const cv::Mat image = drawMapPicture(map, content, &layout);
  EXPECT_NEAR(layout.pixels_per_metre, 700.0 / 5.0, 1e-9) << "4 m and 2 x 0.5 m margin";
  EXPECT_EQ(layout.cols, 700);
}

TEST(MapPicture, WritesAPngOrNamesTheFile)
{
  ExploredMap map;
  map.merge(0.0, 0.0, 0.1, 4, 4, filled(4, 0));
  MapPictureContent content;
  content.path = { { 0.1, 0.1 }, { 0.3, 0.3 } };
  const cv::Mat image = drawMapPicture(map, content);
  const std::string file = testing::TempDir() + "map_picture_test.png";
  writePng(image, file);
  const cv::Mat read = cv::imread(file, cv::IMREAD_COLOR);
  ASSERT_FALSE(read.empty());
  EXPECT_EQ(read.size(), image.size());
  EXPECT_EQ(cv::norm(read, image, cv::NORM_INF), 0.0) << "PNG is lossless";
  std::remove(file.c_str());
  try
  {
    writePng(image, "/nonexistent_dir/map.png");
    FAIL() << "no error for a folder that does not exist";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir/map.png"), std::string::npos) << e.what();
  }
}
}  // namespace
}  // namespace sl_bringup_test
