#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sl_navigation/nav_grid.h"

using sl_navigation::Cell;
using sl_navigation::GridParams;
using sl_navigation::NavGrid;
using sl_navigation::OccupancyView;

namespace
{
/// A 1 x 1 m window of 0.02 m cells with its lower left corner at (x0, y0), all @p value.
struct Window
{
  std::vector<std::int8_t> data;
  OccupancyView view;
  Window(double x0, double y0, std::int8_t value, int cells = 50) : data(cells * cells, value)
  {
    view.data = data.data();
    view.width = view.height = cells;
    view.resolution = 0.02;
    view.origin_x = x0;
    view.origin_y = y0;
  }
  void set(double x, double y, std::int8_t value)
  {
    const int ix = static_cast<int>(std::floor((x - view.origin_x) / view.resolution));
    const int iy = static_cast<int>(std::floor((y - view.origin_y) / view.resolution));
    data[iy * view.width + ix] = value;
  }
};

GridParams small()
{
  GridParams p;
  p.size = 4.0;
  p.resolution = 0.05;
  p.free_persistence = 100.0;
  p.occupied_persistence = 20.0;
  return p;
}
}  // namespace

TEST(NavGrid, StartsUnknownAndCentredOnTheGivenPoint)
{
  NavGrid g(small());
  g.reset(1.0, -1.0);
  EXPECT_EQ(g.width(), 80);
  EXPECT_NEAR(g.originX(), -1.0, 1e-12);
  EXPECT_NEAR(g.originY(), -3.0, 1e-12);
  EXPECT_TRUE(g.contains(2.9, 0.9));
  EXPECT_FALSE(g.contains(3.01, 0.0));
  EXPECT_FALSE(g.contains(std::nan(""), 0.0));
  EXPECT_EQ(g.at(1.0, -1.0, 0.0), Cell::Unknown);
}

TEST(NavGrid, OneOccupiedWindowCellMakesItsCellOccupiedAndTheRestFree)
{
  NavGrid g(small());
  Window w(0.0, 0.0, 0);
  w.set(0.51, 0.51, 100);
  ASSERT_TRUE(g.fuse(w.view, 10.0));
  EXPECT_EQ(g.at(0.52, 0.52, 10.0), Cell::Occupied);
  EXPECT_EQ(g.at(0.57, 0.52, 10.0), Cell::Free);
  EXPECT_EQ(g.at(0.2, 0.8, 10.0), Cell::Free);
  EXPECT_EQ(g.at(-0.2, 0.2, 10.0), Cell::Unknown);  // outside the window
}

TEST(NavGrid, UnknownInTheWindowKeepsWhatWasSeenAndASuspectClearsIt)
{
  NavGrid g(small());
  Window seen(0.0, 0.0, 0);
  seen.set(0.31, 0.31, 100);
  ASSERT_TRUE(g.fuse(seen.view, 1.0));
  Window blind(0.0, 0.0, -1);
  ASSERT_TRUE(g.fuse(blind.view, 2.0));
  EXPECT_EQ(g.at(0.7, 0.7, 2.0), Cell::Free);
  EXPECT_EQ(g.at(0.31, 0.31, 2.0), Cell::Occupied);
  Window suspect(0.0, 0.0, -1);
  suspect.set(0.71, 0.71, 50);
  ASSERT_TRUE(g.fuse(suspect.view, 3.0));
  EXPECT_EQ(g.at(0.71, 0.71, 3.0), Cell::Unknown);
  // Negative evidence: the obstacle's place seen free again.
  Window cleared(0.0, 0.0, 0);
  ASSERT_TRUE(g.fuse(cleared.view, 4.0));
  EXPECT_EQ(g.at(0.31, 0.31, 4.0), Cell::Free);
}

TEST(NavGrid, FreeAndOccupiedLastTheirPersistence)
{
  NavGrid g(small());
  Window w(0.0, 0.0, 0);
  w.set(0.51, 0.51, 100);
  ASSERT_TRUE(g.fuse(w.view, 1000.0));
  EXPECT_EQ(g.at(0.52, 0.52, 1019.0), Cell::Occupied);
  EXPECT_EQ(g.at(0.52, 0.52, 1021.0), Cell::Unknown);
  EXPECT_EQ(g.at(0.2, 0.2, 1099.0), Cell::Free);
  EXPECT_EQ(g.at(0.2, 0.2, 1101.0), Cell::Unknown);
}

TEST(NavGrid, AMapCellHalfSeenIsNotFree)
{
  NavGrid g(small());
  // A window whose last column covers only a fifth of the map cells along its right edge (0.05 m
  // cells, window ending at x = 0.21: the cell [0.20, 0.25) holds one window column of 2.5).
  Window w(0.01, 0.0, 0, 10);
  ASSERT_TRUE(g.fuse(w.view, 1.0));
  EXPECT_EQ(g.at(0.12, 0.12, 1.0), Cell::Free);
  EXPECT_EQ(g.at(0.22, 0.12, 1.0), Cell::Unknown);
}

TEST(NavGrid, RefusesBadWindows)
{
  NavGrid g(small());
  Window w(0.0, 0.0, 0);
  OccupancyView v = w.view;
  v.data = nullptr;
  EXPECT_FALSE(g.fuse(v, 1.0));
  v = w.view;
  v.width = 0;
  EXPECT_FALSE(g.fuse(v, 1.0));
  v = w.view;
  v.origin_x = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(g.fuse(v, 1.0));
  v = w.view;
  v.resolution = -0.02;
  EXPECT_FALSE(g.fuse(v, 1.0));
  EXPECT_FALSE(g.fuse(w.view, std::nan("")));
  v = w.view;
  v.resolution = 0.0002;  // a window this fine would take minutes per step
  EXPECT_FALSE(g.fuse(v, 1.0));
  v = w.view;
  v.origin_x = 1e300;
  EXPECT_FALSE(g.fuse(v, 1.0));
  EXPECT_FALSE(g.contains(1e300, 0.0));
  EXPECT_EQ(g.at(0.5, 0.5, 1.0), Cell::Unknown);
}

TEST(NavGrid, MarkFreeSetsTheBody)
{
  NavGrid g(small());
  g.markFree(0.0, 0.0, 0.12, 5.0);
  EXPECT_EQ(g.at(0.0, 0.0, 5.0), Cell::Free);
  EXPECT_EQ(g.at(0.3, 0.0, 5.0), Cell::Unknown);
  g.markFree(std::nan(""), 0.0, 1.0, 5.0);  // ignored
}

TEST(NavGrid, ValidationNamesTheParameter)
{
  GridParams p = small();
  p.resolution = 0.0;
  try
  {
    NavGrid g(p);
    FAIL() << "accepted a zero resolution";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("map_resolution", 0), 0u) << e.what();
  }
  p = small();
  p.size = 500.0;
  EXPECT_THROW(NavGrid{ p }, std::invalid_argument);
  p = small();
  p.occupied_persistence = std::nan("");
  EXPECT_THROW(NavGrid{ p }, std::invalid_argument);
}

TEST(NavGrid, ToOccupancyWritesTheStates)
{
  NavGrid g(small());
  Window w(0.0, 0.0, 0);
  w.set(0.51, 0.51, 100);
  ASSERT_TRUE(g.fuse(w.view, 1.0));
  std::vector<std::int8_t> out;
  g.toOccupancy(1.0, out);
  ASSERT_EQ(out.size(), 80u * 80u);
  EXPECT_EQ(out[g.indexY(0.52) * 80 + g.indexX(0.52)], 100);
  EXPECT_EQ(out[g.indexY(0.2) * 80 + g.indexX(0.2)], 0);
  EXPECT_EQ(out[0], -1);
}
