// sl_pattern: prints the pattern's sequences or array, or writes the projector frame as PNG.
// No ROS master needed.
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "device/dlp_pico.h"
#include "sl_rig/de_bruijn.h"
#include "sl_rig/pattern.h"
#include "sl_rig/tool_args.h"

namespace
{
const char* kUsage =
    "usage: sl_pattern [options] (--sequences | --array | --png FILE | --dlp-bytes)...\n"
    "  --sequences        print G(4,3) and G(4,2), one line each\n"
    "  --array            print the value array, one row per line\n"
    "  --png FILE         write the projector frame (mono8 PNG)\n"
    "  --dlp-bytes        print the DLP Pico I2C set-up bytes (device 0x1b)\n"
    "options (defaults are the prototype's):\n"
    "  --rows N (16) --cols N (64) --primitive WxH (5x9) --gap XxY (2x6)\n"
    "  --offset XxY (0x0) --size WxH (480x320) --flip-x --flip-y\n";

int toInt(const std::string& option, const std::string& text)
{
  size_t used = 0;
  int v = 0;
  try
  {
    v = std::stoi(text, &used);
  }
  catch (const std::exception&)
  {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw std::invalid_argument(option + " expects an integer, got '" + text + "'");
  return v;
}

void toPair(const std::string& option, const std::string& text, int& a, int& b)
{
  const size_t x = text.find('x');
  if (x == std::string::npos)
    throw std::invalid_argument(option + " expects AxB, got '" + text + "'");
  a = toInt(option, text.substr(0, x));
  b = toInt(option, text.substr(x + 1));
}
}  // namespace

int main(int argc, char** argv)
{
  sl_projector::PatternConfig config;
  bool sequences = false, array = false, dlp = false;
  std::string png;
  try
  {
    sl_rig::ToolArgs args(argc, argv);
    for (std::string a; args.next(a);)
    {
      if (a == "--sequences")
        sequences = true;
      else if (a == "--array")
        array = true;
      else if (a == "--dlp-bytes")
        dlp = true;
      else if (a == "--png")
        png = args.value();
      else if (a == "--rows")
        config.rows = static_cast<int>(args.integer(1, 1000));
      else if (a == "--cols")
        config.cols = static_cast<int>(args.integer(1, 1000));
      else if (a == "--primitive")
        toPair(a, args.value(), config.primitive_width, config.primitive_height);
      else if (a == "--gap")
        toPair(a, args.value(), config.gap_x, config.gap_y);
      else if (a == "--offset")
        toPair(a, args.value(), config.offset_x, config.offset_y);
      else if (a == "--size")
        toPair(a, args.value(), config.projector_width, config.projector_height);
      else if (a == "--flip-x")
        config.flip_x = true;
      else if (a == "--flip-y")
        config.flip_y = true;
      else if (a == "-h" || a == "--help")
      {
        std::cout << kUsage;
        return 0;
      }
      else
        args.unknown();
    }
    if (!sequences && !array && png.empty() && !dlp)
      throw std::invalid_argument("nothing to do");

    if (sequences)
    {
      std::cout << "G(4,3) = " << sl_projector::sequenceToString(sl_projector::deBruijnSequence(4, 3)) << "\n";
      std::cout << "G(4,2) = " << sl_projector::sequenceToString(sl_projector::deBruijnSequence(4, 2)) << "\n";
    }
    if (dlp)
      std::cout << sl_projector::formatWrites(0x1b, sl_projector::dlpPicoSetup());
    if (array || !png.empty())
    {
      const sl_projector::Pattern pattern(config);
      if (array)
      {
        const sl_projector::PatternArray& arr = pattern.array();
        for (int r = 0; r < arr.rows(); ++r)
        {
          std::string line;
          for (int c = 0; c < arr.cols(); ++c)
            line.push_back(static_cast<char>('0' + arr.value(r, c)));
          std::cout << line << "\n";
        }
      }
      if (!png.empty())
      {
        if (!cv::imwrite(png, pattern.render()))
          throw std::runtime_error("cannot write " + png);
        std::cerr << "wrote " << png << "\n";
      }
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "sl_pattern: " << e.what() << "\n" << kUsage;
    return 2;
  }
  return 0;
}
