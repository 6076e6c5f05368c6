// sl_calibrate_full: full projector-camera calibration from recorded images. The camera from
// checkerboard views (OpenCV calibrateCamera) or a ROS camera_calibration file; the projector as an
// inverse camera from the decoded pattern on >= 3 plane poses, each fixed by a checkerboard on the
// plane or by a known distance. Writes the rig (calibration) file. No ROS master needed.
#include <iostream>
#include <string>
#include <vector>

#include "calibration_tool.h"
#include "sl_calibration/full_calibration.h"
#include "sl_calibration/residual_plot.h"

namespace
{
using namespace sl_calibration;

const char* kUsage =
    "usage: sl_calibrate_full --rig RIG.yaml --out OUT.yaml --board COLSxROWS --square S [views] [options]\n"
    "Full calibration: camera intrinsics and distortion, projector intrinsics, distortion and pose.\n"
    "  --rig FILE            the rig file to start from (pattern, mount, projector frame size; its\n"
    "                        geometry is used to decode the pattern and need only be roughly right;\n"
    "                        its depth_tables are kept)\n"
    "  --out FILE            the calibration file to write\n"
    "  --board COLSxROWS     checkerboard INNER corners, as ROS camera_calibration's --size (a board\n"
    "                        of 9 x 6 squares is 8x5)\n"
    "  --square S            square size, m\n"
    "views (repeatable; images are files, --camera-view also takes a folder):\n"
    "  --camera-view IMAGE   a checkerboard image for the camera (lights on, projector dark)\n"
    "  --pose BOARD,PATTERN  one pose of a calibration plane: the checkerboard image (lights on,\n"
    "                        projector dark) and the pattern image of the same pose (projector on,\n"
    "                        board covered or outside the pattern); the board image is a camera view too\n"
    "  --plane PATTERN:D     the pattern image of a plane perpendicular to the robot at D m (as in\n"
    "                        sl_calibrate_plane, see --reference / --normal)\n"
    "options:\n"
    "  --camera-info FILE    use this camera model (ROS camera_calibration's YAML) instead of\n"
    "                        calibrating the camera; board images then only give plane poses\n"
    "  --camera-info-out FILE  also write the camera model as camera_info YAML (camera driver)\n"
    "  --residuals FILE.png  also draw the camera's reprojection residuals of the board corners over\n"
    "                        the image (arrows magnified by the factor in the legend; one colour per view)\n"
    "  --reference R, --normal N  how --plane distances are defined (camera|edge, robot|camera)\n"
    "  --k3                  also estimate k3 (camera and projector; default k3 = 0)\n"
    "  --epipolar-tolerance PX  decoder tolerance for the uncalibrated rig (default 10)\n"
    "  --no-joint            skip the final joint refinement (bundle adjustment) of camera, projector,\n"
    "                        pose and board poses; keep the separate camera and projector fits\n"
    "Needs >= 3 plane poses (--pose or --plane) and, without --camera-info, >= 3 board images.\n"
    "Exit status: 0 written, 1 calibration failed (nothing written), 2 bad arguments.\n";

struct PoseArg
{
  std::string board, pattern;
};

/// The options of this tool beyond the common ones, and the views.
struct FullArgs
{
  std::string board_size, camera_info, camera_info_out, residuals;
  double square = 0.0;
  FullCalibrationOptions options;
  std::vector<std::string> camera_views;
  std::vector<PoseArg> poses;
  std::vector<std::pair<std::string, double>> planes;

  bool read(const std::string& a, sl_rig::ToolArgs& args, tool::CommonOptions&)
  {
    if (a == "--board")
      board_size = args.value();
    else if (a == "--square")
      square = args.number();
    else if (a == "--camera-view")
      camera_views.push_back(args.value());
    else if (a == "--pose")
      poses.push_back(parsePose(args.value()));
    else if (a == "--plane")
    {
      std::string path;
      double d = 0.0;
      parsePathAndNumber(args.value(), path, d);
      planes.emplace_back(path, d);
    }
    else if (a == "--camera-info")
      camera_info = args.value();
    else if (a == "--camera-info-out")
      camera_info_out = args.value();
    else if (a == "--residuals")
      residuals = tool::outputFile(args, ".png");
    else if (a == "--k3")
      options.camera.fix_k3 = options.projector.fix_k3 = false;
    else if (a == "--no-joint")
      options.joint_refinement = false;
    else
      return false;
    return true;
  }

  void check() const
  {
    if (board_size.empty() && (!camera_views.empty() || !poses.empty()))
      throw std::invalid_argument("--board and --square are required with board images");
    if (!residuals.empty() && camera_views.empty() && poses.empty())
      throw std::invalid_argument("--residuals " + residuals +
                                  ": the camera's residuals need board images (--camera-view or --pose)");
  }

  static PoseArg parsePose(const std::string& v)
  {
    const size_t comma = v.find(',');
    if (comma == std::string::npos || comma == 0 || comma + 1 == v.size())
      throw std::invalid_argument("--pose needs BOARD_IMAGE,PATTERN_IMAGE, got '" + v + "'");
    return PoseArg{ v.substr(0, comma), v.substr(comma + 1) };
  }
};

/// Adds every view of @p a to @p calibration, saying what was found in each ("view 3 of 16: ...").
void addViews(const FullArgs& a, FullCalibration& calibration)
{
  std::vector<std::string> camera_files;
  for (const std::string& v : a.camera_views)
    for (const std::string& file : listImages(v))
      camera_files.push_back(file);
  const size_t views = camera_files.size() + a.poses.size() + a.planes.size();
  size_t n = 0;
  auto progress = [&] { return "view " + std::to_string(++n) + " of " + std::to_string(views); };
  for (const std::string& file : camera_files)
  {
    calibration.addCameraView(file, readGreyImage(file));
    std::cout << progress() << ": " << file << ": checkerboard found" << std::endl;
  }
  for (const PoseArg& p : a.poses)
  {
    calibration.addPlaneView(p.board, readGreyImage(p.board), p.pattern, readGreyImage(p.pattern));
    std::cout << progress() << ", plane pose: " << p.board << ": checkerboard found; " << p.pattern
              << ": pattern decoded" << std::endl;
  }
  for (const auto& p : a.planes)
  {
    calibration.addDistanceView(p.first, readGreyImage(p.first), p.second);
    std::cout << progress() << ", plane at " << fixed(p.second, 3) << " m: " << p.first << ": pattern decoded"
              << std::endl;
  }
  std::cout << "calibrating from " << calibration.boardViews() << " board views and " << calibration.planeViews()
            << " plane views ..." << std::endl;
}

/// Calibrates and writes the output file(s); @p written is set once the calibration file is.
void calibrate(const tool::CommonOptions& common, const FullArgs& a, bool& written)
{
  FullCalibrationOptions options = a.options;
  options.distance_planes = common.planes;
  options.epipolar_tolerance = common.epipolar_tolerance;
  const sl_projector::Rig rig = sl_projector::loadRig(common.rig_path);
  Board board;
  if (!a.board_size.empty())
    board = parseBoardSize(a.board_size, a.square);
  FullCalibration calibration(rig, board, options);
  if (!a.camera_info.empty())
    calibration.setCamera(loadCameraInfo(a.camera_info));
  addViews(a, calibration);
  const FullCalibrationResult res = calibration.calibrate();
  std::cout << "\n" << res.summary();
  sl_projector::saveRig(res.rig, common.out_path);
  written = true;
  std::cout << "wrote " << common.out_path
            << (rig.tables.rational.empty() && rig.tables.linear.empty()
                    ? std::string()
                    : std::string(" (depth_tables kept from ") + common.rig_path + ")")
            << "\n";
  if (!a.camera_info_out.empty())
  {
    saveCameraInfo(res.rig.camera, a.camera_info_out);
    std::cout << "wrote " << a.camera_info_out << " (camera_info)\n";
  }
  if (!a.residuals.empty())
  {
    writeCameraResidualPlot(a.residuals, res);
    std::cout << "wrote " << a.residuals << " (camera reprojection residuals of " << res.camera_residuals.size()
              << " board corners)\n";
  }
}
}  // namespace

int main(int argc, char** argv)
{
  return tool::run<FullArgs>("sl_calibrate_full", kUsage, argc, argv, calibrate);
}
