// The camera's side of the full calibration without images: camera_info files in and out (ours
// and ROS camera_calibration's), their errors, and the board size.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <unistd.h>

#include "sl_calibration/camera_calibration.h"
#include "test_rig.h"

using namespace sl_calibration;

TEST(CalibrationCamera, CameraInfoRoundTripAndErrors)
{
  const sl_projector::PinholeModel& cam = trueRig().camera;
  const std::string prefix = ::testing::TempDir() + "/sl_calibration_" + std::to_string(getpid()) + "_";
  const std::string path = prefix + "camera_info.yaml";
  saveCameraInfo(cam, path, "sl_camera");
  const sl_projector::PinholeModel back = loadCameraInfo(path);
  EXPECT_EQ(back.width, cam.width);
  EXPECT_DOUBLE_EQ(back.fx, cam.fx);
  EXPECT_DOUBLE_EQ(back.cy, cam.cy);
  for (size_t i = 0; i < 5; ++i)
    EXPECT_DOUBLE_EQ(back.dist[i], cam.dist[i]);
  // ROS camera_calibration's layout, 5 coefficients, block style.
  const std::string ros = prefix + "ost.yaml";
  {
    std::ofstream o(ros);
    o << "image_width: 752\nimage_height: 480\ncamera_name: narrow_stereo\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
         "  data: [1490.5, 0, 371.2, 0, 1491.5, 244.1, 0, 0, 1]\ndistortion_model: plumb_bob\n"
         "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [-0.081, 0.13, 0.0004, -0.0002, 0]\n"
         "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"
         "projection_matrix:\n  rows: 3\n  cols: 4\n  data: [1490.5, 0, 371.2, 0, 0, 1491.5, 244.1, 0, 0, 0, 1, 0]\n";
  }
  const sl_projector::PinholeModel r = loadCameraInfo(ros);
  EXPECT_DOUBLE_EQ(r.fy, 1491.5);
  EXPECT_DOUBLE_EQ(r.dist[1], 0.13);
  const std::string bad = prefix + "bad.yaml";
  {
    std::ofstream o(bad);
    o << "image_width: 752\nimage_height: 480\ncamera_matrix:\n  data: [1, 0, 2]\n";
  }
  try
  {
    loadCameraInfo(bad);
    FAIL();
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("camera_matrix.data: has 3 numbers, expected 9"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(loadCameraInfo(prefix + "does_not_exist.yaml"), CalibrationError);
  for (const std::string& f : { path, ros, bad })
    std::remove(f.c_str());
}

TEST(CalibrationCamera, BoardSizeParsing)
{
  const Board b = parseBoardSize("9x6", 0.022);
  EXPECT_EQ(b.cols, 9);
  EXPECT_EQ(b.rows, 6);
  EXPECT_EQ(b.objectPoints().size(), 54u);
  EXPECT_THROW(parseBoardSize("9by6", 0.022), std::invalid_argument);
  EXPECT_THROW(parseBoardSize("6x6", 0.022), std::invalid_argument);  // symmetric: orientation ambiguous
  EXPECT_THROW(parseBoardSize("9x6", 22.0), std::invalid_argument);   // mm given
}
