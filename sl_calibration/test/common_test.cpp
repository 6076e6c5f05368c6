// The small helpers of the calibration tools: "PATH:NUMBER", number lists, the distance
// reference, image folders and unreadable images.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include <unistd.h>

#include "sl_calibration/plane_calibration.h"

using namespace sl_calibration;

namespace
{
/// A path in the test's temporary directory, unique to this process (tests of other workspaces may
/// run at the same time).
std::string tempPath(const std::string& name)
{
  return ::testing::TempDir() + "/sl_calibration_" + std::to_string(getpid()) + "_" + name;
}
}  // namespace

TEST(CalibrationTools, ParsingHelpers)
{
  std::string path;
  double d = 0.0;
  parsePathAndNumber("/data/a:b/plane.png:0.55", path, d);
  EXPECT_EQ(path, "/data/a:b/plane.png");
  EXPECT_DOUBLE_EQ(d, 0.55);
  EXPECT_THROW(parsePathAndNumber("plane.png", path, d), CalibrationError);
  EXPECT_THROW(parsePathAndNumber("plane.png:far", path, d), CalibrationError);
  EXPECT_EQ(parseNumberList("0.5,0.6,0.7"), (std::vector<double>{ 0.5, 0.6, 0.7 }));
  EXPECT_THROW(parseNumberList("0.5,,0.7"), std::invalid_argument);
  EXPECT_EQ(parseDistanceReference("edge"), DistanceReference::Edge);
  EXPECT_THROW(parseDistanceReference("wall"), std::invalid_argument);
  EXPECT_THROW(listImages(tempPath("no_such_folder")), CalibrationError);
  const std::string empty = tempPath("calibration_empty");
  std::system(("rm -rf '" + empty + "' && mkdir -p '" + empty + "'").c_str());
  try
  {
    listImages(empty);
    FAIL();
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("the folder has no images"), std::string::npos) << e.what();
  }
  std::ofstream(empty + "/broken.png") << "not a png";
  EXPECT_THROW(readGreyImage(empty + "/broken.png"), CalibrationError);
  std::system(("rm -rf '" + empty + "'").c_str());
}
