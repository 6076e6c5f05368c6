// sl_decode: decodes one image file with a calibration file, no ROS master needed.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "sl_decoder/decoder.h"
#include "sl_decoder/ray_classifier.h"
#include "sl_rig/mono8.h"
#include "sl_rig/tool_args.h"

namespace
{
const char* kUsage =
    "usage: sl_decode --calibration CAL.yaml [--csv OUT.csv] [--rays-csv RAYS.csv] [--repeat N] [--depth-mode MODE]\n"
    "                 IMAGE.png\n"
    "  decodes IMAGE (mono8, or 16-bit/colour converted to mono8) with the rig in CAL.yaml and prints\n"
    "  decoded=<blobs identified> valid=<points written> time_ms_median=<median decode time over N runs>\n"
    "  --csv writes one line per valid primitive: u,v,row,col,x,y,z,confidence (px; m, camera optical frame)\n"
    "  --rays-csv writes the outcome of every primitive's ray (default ray settings): row,col,state,depth\n"
    "    (state decoded, floor, dark, lit or unseen; depth: camera z of the ray's end point, m; empty for unseen)\n"
    "  --depth-mode triangulation (default), rational or linear (needs the calibration's depth tables)\n";

/// Writes one line per primitive: row,col,state,depth. @throws std::runtime_error naming the file.
void writeRaysCsv(const std::string& path, const sl_projector::Rig& rig, const sl_decoder::DecoderConfig& config,
                  const cv::Mat& mono, const sl_decoder::DecodeResult& result)
{
  std::ofstream out(path);
  if (!out)
    throw std::runtime_error("cannot write '" + path + "'");
  sl_decoder::RayClassifier classifier(rig, config, sl_decoder::RayConfig());
  std::vector<sl_decoder::RayOutcome> outcomes;
  classifier.classify(mono, result, outcomes);
  out << "row,col,state,depth\n" << std::setprecision(6);
  const int cols = rig.pattern.cols;
  for (size_t i = 0; i < outcomes.size(); ++i)
  {
    const sl_decoder::RayOutcome& o = outcomes[i];
    out << i / static_cast<size_t>(cols) << "," << i % static_cast<size_t>(cols) << "," << sl_decoder::toString(o.state)
        << ",";
    if (o.state != sl_decoder::RayState::Unseen)
      out << o.depth;
    out << "\n";
  }
  if (!out)
    throw std::runtime_error("write to '" + path + "' failed");
}
}  // namespace

int main(int argc, char** argv)
{
  std::string calibration, csv, rays_csv, image_path, mode = "triangulation";
  int repeat = 1;
  try
  {
    sl_rig::ToolArgs args(argc, argv);
    for (std::string a; args.next(a);)
    {
      if (a == "--calibration")
        calibration = args.value();
      else if (a == "--csv")
        csv = args.value();
      else if (a == "--rays-csv")
        rays_csv = args.value();
      else if (a == "--repeat")
        repeat = static_cast<int>(args.integer(1, 1000000));
      else if (a == "--depth-mode")
        mode = args.value();
      else if (a == "-h" || a == "--help")
      {
        std::cout << kUsage;
        return 0;
      }
      else if (!a.empty() && a[0] == '-')
        args.unknown();
      else if (image_path.empty())
        image_path = a;
      else
        throw std::invalid_argument("one image only, got '" + a + "' too");
    }
    if (calibration.empty())
      throw std::invalid_argument("--calibration is required");
    if (image_path.empty())
      throw std::invalid_argument("no image given");

    const sl_projector::Rig rig = sl_projector::loadRig(calibration);
    sl_decoder::DecoderConfig config;
    config.depth_mode = sl_decoder::parseDepthMode(mode);
    sl_decoder::Decoder decoder(rig, config);

    const cv::Mat raw = cv::imread(image_path, cv::IMREAD_UNCHANGED);
    if (raw.empty())
      throw std::runtime_error("cannot read image '" + image_path + "'");
    std::string encoding;
    switch (raw.type())
    {
      case CV_8UC1:
        encoding = "mono8";
        break;
      case CV_16UC1:
        encoding = "mono16";
        break;
      case CV_8UC3:
        encoding = "bgr8";
        break;
      case CV_8UC4:
        encoding = "bgra8";
        break;
      default:
        throw std::invalid_argument("image '" + image_path + "' has an unsupported pixel type");
    }
    bool converted = false;
    const cv::Mat mono = sl_rig::toMono8(raw, encoding, converted);
    if (converted)
      std::cerr << "sl_decode: converted " << encoding << " to mono8\n";

    sl_decoder::DecodeResult result;
    std::vector<double> times;
    for (int k = 0; k < repeat; ++k)
    {
      decoder.decode(mono, result);
      times.push_back(result.times.total);
    }
    std::sort(times.begin(), times.end());
    const double median =
        times.size() % 2 ? times[times.size() / 2] : 0.5 * (times[times.size() / 2 - 1] + times[times.size() / 2]);

    if (!csv.empty())
    {
      std::ofstream out(csv);
      if (!out)
        throw std::runtime_error("cannot write '" + csv + "'");
      out << "u,v,row,col,x,y,z,confidence\n" << std::setprecision(9);
      for (const sl_decoder::Blob& b : result.blobs)
        if (b.valid)
          out << b.u << "," << b.v << "," << b.row << "," << b.col << "," << b.x << "," << b.y << "," << b.z << ","
              << b.confidence << "\n";
      if (!out)
        throw std::runtime_error("write to '" + csv + "' failed");
    }
    if (!rays_csv.empty())
      writeRaysCsv(rays_csv, rig, config, mono, result);
    std::cout << "decoded=" << result.identified << " valid=" << result.valid << " time_ms_median=" << std::fixed
              << std::setprecision(3) << median << "\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "sl_decode: " << e.what() << "\n" << kUsage;
    return 2;
  }
  return 0;
}
