#pragma once
// What sl_calibrate_plane and sl_calibrate_full share: the options both read, and the frame both run
// in (exit status 0: written; 1: the calibration failed, nothing written; 2: bad arguments).
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "sl_calibration/plane_calibration.h"
#include "sl_rig/tool_args.h"

namespace sl_calibration
{
namespace tool
{

/**
 * The file name that follows an output option (the current one of @p args): not another option,
 * ending in @p extension (empty: any), in a folder that exists and may be written, so that a long
 * run does not end in a file it cannot write. @throws std::invalid_argument naming the option and
 * the file.
 */
inline std::string outputFile(sl_rig::ToolArgs& args, const std::string& extension = "")
{
  const std::string option = args.option();
  const std::string path = args.value();
  if (path.empty() || path[0] == '-')
    throw std::invalid_argument(option + " needs a file name, got '" + path + "'");
  if (!extension.empty() && (path.size() <= extension.size() ||
                             path.compare(path.size() - extension.size(), extension.size(), extension) != 0))
    throw std::invalid_argument(option + " " + path + ": the file name must end in " + extension);
  const size_t slash = path.find_last_of('/');
  if (slash + 1 == path.size())
    throw std::invalid_argument(option + " " + path + ": a folder, not a file name");
  const std::string folder = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  if (access(folder.c_str(), W_OK) != 0)
    throw std::invalid_argument(option + " " + path + ": cannot write there (" + folder +
                                " does not exist or may not be written)");
  return path;
}

/// The options of both tools: the rig file to start from, the file to write, how known distances
/// define planes, and the decoder's tolerance for the uncalibrated rig.
struct CommonOptions
{
  std::string rig_path, out_path;
  PlaneCalibrationOptions planes;
  double epipolar_tolerance = kCalibrationEpipolarTolerance;

  /// Reads @p option if it is one of them; false otherwise.
  bool read(const std::string& option, sl_rig::ToolArgs& args)
  {
    if (option == "--rig")
      rig_path = args.value();
    else if (option == "--out")
      out_path = args.value();
    else if (option == "--reference")
      planes.reference = parseDistanceReference(args.value());
    else if (option == "--normal")
      planes.normal = parsePlaneNormal(args.value());
    else if (option == "--epipolar-tolerance")
      epipolar_tolerance = args.number();
    else
      return false;
    return true;
  }
};

/// Reads one option of the tool's own; false for an unknown one.
using ReadOption = std::function<bool(const std::string& option, sl_rig::ToolArgs& args)>;

/**
 * Runs a calibration tool: reads the arguments (-h / --help prints @p usage; @p common's options,
 * then @p read_option), checks them (--rig and --out given, then @p check, then the plane options),
 * and calls @p calibrate, which sets its argument once the output file is written.
 * @return the exit status.
 */
inline int run(const std::string& name, const char* usage, int argc, char** argv, CommonOptions& common,
               const ReadOption& read_option, const std::function<void()>& check,
               const std::function<void(bool& written)>& calibrate)
{
  try
  {
    sl_rig::ToolArgs args(argc, argv);
    for (std::string a; args.next(a);)
    {
      if (a == "-h" || a == "--help")
      {
        std::cout << usage;
        return 0;
      }
      if (!common.read(a, args) && !read_option(a, args))
        args.unknown();
    }
    if (common.rig_path.empty() || common.out_path.empty())
      throw std::invalid_argument("--rig and --out are required");
    check();
    common.planes.validate();
  }
  catch (const std::exception& e)
  {
    std::cerr << name << ": " << e.what() << "\n" << usage;
    return 2;
  }
  bool written = false;
  try
  {
    calibrate(written);
  }
  catch (const std::exception& e)
  {
    std::cerr << name << ": " << e.what() << (written ? "\n" : "\nnothing written.\n");
    return 1;
  }
  return 0;
}

/**
 * Runs the tool whose own options are an @p Args (`bool read(option, args, common)`, `void check()`)
 * and whose work is @p calibrate (it sets `written` once the output file is written).
 */
template <typename Args>
int run(const std::string& name, const char* usage, int argc, char** argv,
        void (*calibrate)(const CommonOptions& common, const Args& args, bool& written))
{
  CommonOptions common;
  Args a;
  return run(
      name, usage, argc, argv, common,
      [&](const std::string& option, sl_rig::ToolArgs& args) { return a.read(option, args, common); },
      [&] { a.check(); }, [&](bool& written) { calibrate(common, a, written); });
}

}  // namespace tool
}  // namespace sl_calibration
