#include "sl_calibration/common.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <dirent.h>
#include <sys/stat.h>

#include <opencv2/imgcodecs.hpp>

#include "sl_rig/mono8.h"

namespace sl_calibration
{

bool CalibrationPlane::intersect(const Eigen::Vector3d& ray, Eigen::Vector3d& point) const
{
  const double denom = normal.dot(ray);
  if (std::abs(denom) < 1e-9 * ray.norm())
    return false;
  const double s = offset / denom;
  if (!(s > 0.0) || !std::isfinite(s))
    return false;
  point = s * ray;
  return point.z() > 0.0;
}

std::vector<PrimitiveSample> decodedSamples(const sl_decoder::DecodeResult& result)
{
  std::vector<PrimitiveSample> out;
  out.reserve(static_cast<size_t>(result.valid));
  for (const sl_decoder::Blob& b : result.blobs)
    if (b.decoded() && b.valid)
      out.push_back(PrimitiveSample{ b.row, b.col, b.u, b.v });
  return out;
}

sl_decoder::DecoderConfig calibrationDecoderConfig(double epipolar_tolerance)
{
  sl_decoder::DecoderConfig config;
  config.depth_mode = sl_decoder::DepthMode::Triangulation;
  config.epipolar_tolerance = epipolar_tolerance;
  config.identify_by_words = true;
  config.validate();
  return config;
}

cv::Mat readGreyImage(const std::string& path)
{
  struct stat st;
  if (stat(path.c_str(), &st) != 0)
    throw CalibrationError(path + ": no such file");
  cv::Mat image = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (image.empty())
    throw CalibrationError(path + ": cannot read the image (not an image file OpenCV reads?)");
  cv::Mat grey;
  try
  {
    sl_rig::toMono8(image, grey);  // colour to luma, 16 bits to their top 8
  }
  catch (const std::invalid_argument& e)
  {
    throw CalibrationError(path + ": unsupported pixel type (" + e.what() + ")");
  }
  return grey;
}

namespace
{
bool hasImageExtension(const std::string& name)
{
  const size_t dot = name.find_last_of('.');
  if (dot == std::string::npos)
    return false;
  std::string ext = name.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const char* kExt[] = { "png", "jpg", "jpeg", "pgm", "ppm", "pnm", "bmp", "tif", "tiff" };
  for (const char* e : kExt)
    if (ext == e)
      return true;
  return false;
}
}  // namespace

std::vector<std::string> listImages(const std::string& path)
{
  struct stat st;
  if (stat(path.c_str(), &st) != 0)
    throw CalibrationError(path + ": no such file or folder");
  if (!S_ISDIR(st.st_mode))
    return { path };
  std::vector<std::string> out;
  DIR* d = opendir(path.c_str());
  if (!d)
    throw CalibrationError(path + ": cannot open the folder");
  while (dirent* e = readdir(d))
  {
    const std::string name = e->d_name;
    if (hasImageExtension(name))
      out.push_back(path + (path.back() == '/' ? "" : "/") + name);
  }
  closedir(d);
  std::sort(out.begin(), out.end());
  if (out.empty())
    throw CalibrationError(path + ": the folder has no images (png, jpg, pgm, bmp, tif ...)");
  return out;
}

void parsePathAndNumber(const std::string& spec, std::string& path, double& number)
{
  const size_t colon = spec.find_last_of(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size())
    throw CalibrationError("'" + spec + "': expected PATH:DISTANCE_M (e.g. plane_500.png:0.5)");
  path = spec.substr(0, colon);
  const std::string text = spec.substr(colon + 1);
  char* end = nullptr;
  number = std::strtod(text.c_str(), &end);
  if (!end || *end != '\0' || !std::isfinite(number))
    throw CalibrationError("'" + spec + "': '" + text + "' is not a number (distance in metres)");
}

std::vector<double> parseNumberList(const std::string& text)
{
  std::vector<double> out;
  size_t start = 0;
  while (start <= text.size())
  {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || !end || *end != '\0' || !std::isfinite(v))
      throw std::invalid_argument("'" + text + "' is not a comma-separated list of numbers");
    out.push_back(v);
    if (comma == std::string::npos)
      break;
    start = comma + 1;
  }
  return out;
}

double rotationAngle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b)
{
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

std::string fixed(double value, int digits)
{
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

}  // namespace sl_calibration
