// sl_calibrate_plane: plane calibration from recorded data. Decodes images of a flat plane at known
// distances, fits per primitive the prototype's linear model and the rational model, reports the
// residuals and writes the tables into the rig (calibration) file. No ROS master needed.
#include <algorithm>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "calibration_tool.h"
#include "sl_calibration/plane_calibration.h"
#include "sl_calibration/residual_plot.h"
#include "sl_rig/mono8.h"

#ifdef SL_CALIBRATION_WITH_ROSBAG
#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgcodecs.hpp>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#endif

namespace
{
using namespace sl_calibration;

const char* kUsage =
    "usage: sl_calibrate_plane --rig RIG.yaml --out OUT.yaml [options] SOURCE:DISTANCE ...\n"
    "Plane calibration: a flat plane perpendicular to the robot at N >= 3 known distances.\n"
    "  SOURCE:DISTANCE  images of the plane at DISTANCE m: an image file, a folder of images, or a\n"
    "                   .bag file (every image on --topic); repeat for every distance (several\n"
    "                   sources may share a distance; each primitive's position there is the median)\n"
    "  --rig FILE       the rig file to start from (camera, mount, pattern; its geometry is used to\n"
    "                   decode and need only be roughly right)\n"
    "  --out FILE       the calibration file to write: the rig with depth_tables (linear, rational)\n"
    "  --reference R    what DISTANCE is measured from: camera (default: the camera's optical centre,\n"
    "                   along the robot's x axis) or edge (the robot's front edge, platform_edge)\n"
    "  --normal N       the plane is perpendicular to the robot's x axis (robot, default) or to the\n"
    "                   camera's optical axis (camera; DISTANCE then along that axis)\n"
    "  --min-distances N  distances a primitive must be seen at to be calibrated (default 3)\n"
    "  --max-rms MM     reject primitives whose rational fit leaves more (default 3 mm)\n"
    "  --epipolar-tolerance PX  decoder tolerance for the uncalibrated rig (default 10)\n"
    "  --residuals FILE.csv     write per-primitive residuals (mm) at every distance\n"
    "  --residuals FILE.png     draw the rational model's residuals over the image: per primitive and\n"
    "                           distance, the column where its model puts the plane minus the column\n"
    "                           where it was seen (arrows magnified by the factor in the legend; one\n"
    "                           colour per distance); give --residuals twice for both files\n"
    "  --topic TOPIC    image topic in bags (default: the only sensor_msgs/Image topic)\n"
    "Exit status: 0 written, 1 calibration failed (nothing written), 2 bad arguments.\n";

struct Source
{
  std::string path;
  double distance;
};

bool endsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Called with every image of a source and its name in messages.
using AddImage = std::function<void(const std::string& name, const cv::Mat& grey)>;

#ifdef SL_CALIBRATION_WITH_ROSBAG
/// The only image topic (sensor_msgs/Image or CompressedImage) of @p bag.
std::string onlyImageTopic(const rosbag::Bag& bag, const std::string& path)
{
  rosbag::View all(bag);
  std::vector<std::string> image_topics;
  for (const rosbag::ConnectionInfo* c : all.getConnections())
    if ((c->datatype == "sensor_msgs/Image" || c->datatype == "sensor_msgs/CompressedImage") &&
        std::find(image_topics.begin(), image_topics.end(), c->topic) == image_topics.end())
      image_topics.push_back(c->topic);
  if (image_topics.size() != 1)
  {
    std::string list;
    for (const std::string& t : image_topics)
      list += " " + t;
    throw CalibrationError(path + ": " +
                           (image_topics.empty() ? std::string("no image topic in the bag")
                                                 : "several image topics, choose one with --topic:" + list));
  }
  return image_topics.front();
}

/// The image of a bag message as 8-bit grey. @throws CalibrationError naming @p name.
cv::Mat greyImageOf(const rosbag::MessageInstance& m, const std::string& name)
{
  cv::Mat grey;
  try
  {
    if (sensor_msgs::Image::ConstPtr img = m.instantiate<sensor_msgs::Image>())
    {
      bool converted = false;
      grey = sl_rig::toMono8(cv_bridge::toCvShare(img)->image, img->encoding, converted).clone();
    }
    else if (sensor_msgs::CompressedImage::ConstPtr c = m.instantiate<sensor_msgs::CompressedImage>())
      grey = cv::imdecode(c->data, cv::IMREAD_GRAYSCALE);
  }
  catch (const std::exception& e)
  {
    throw CalibrationError(name + ": cannot convert the image: " + e.what());
  }
  if (grey.empty())
    throw CalibrationError(name + ": not an image it can read");
  return grey;
}
#endif

/// Calls @p add for every image on @p topic (empty: the only image topic) of the bag @p path;
/// returns the number of images.
int forEachBagImage(const std::string& path, const std::string& topic, const AddImage& add)
{
#ifdef SL_CALIBRATION_WITH_ROSBAG
  rosbag::Bag bag;
  try
  {
    bag.open(path, rosbag::bagmode::Read);
  }
  catch (const std::exception& e)
  {
    throw CalibrationError(path + ": cannot open the bag: " + e.what());
  }
  const std::string chosen = topic.empty() ? onlyImageTopic(bag, path) : topic;
  rosbag::View view(bag, rosbag::TopicQuery(chosen));
  int n = 0;
  for (const rosbag::MessageInstance& m : view)
  {
    const std::string name = path + "[" + chosen + " #" + std::to_string(n) + "]";
    add(name, greyImageOf(m, name));
    ++n;
  }
  if (n == 0)
    throw CalibrationError(path + ": no messages on " + chosen);
  return n;
#else
  (void)topic;
  (void)add;
  throw CalibrationError(path + ": this sl_calibrate_plane was built without rosbag (librosbag-dev)");
#endif
}

/// Calls @p add for every image of a source (a bag, a folder or an image file); returns the
/// number of images.
int forEachImage(const Source& source, const std::string& topic, const AddImage& add)
{
  if (endsWith(source.path, ".bag"))
    return forEachBagImage(source.path, topic, add);
  int n = 0;
  for (const std::string& file : listImages(source.path))
  {
    add(file, readGreyImage(file));
    ++n;
  }
  return n;
}

/// The options of this tool beyond the common ones (the plane options are there too), and the sources.
struct PlaneArgs
{
  std::string residuals_csv, residuals_png, topic;
  std::vector<Source> sources;

  bool read(const std::string& a, sl_rig::ToolArgs& args, tool::CommonOptions& common)
  {
    PlaneCalibrationOptions& options = common.planes;
    if (a == "--min-distances")
      options.min_distances = static_cast<int>(args.integer(1, 1000));
    else if (a == "--max-rms")
      options.max_rational_rms = args.number() / 1000.0;
    else if (a == "--residuals")
    {
      const std::string path = tool::outputFile(args);
      std::string& slot = isPngPath(path) ? residuals_png : residuals_csv;
      if (!slot.empty())
        throw std::invalid_argument("--residuals " + path + ": a " + (isPngPath(path) ? "picture" : "CSV file") +
                                    " is asked for already (" + slot + ")");
      slot = path;
    }
    else if (a == "--topic")
      topic = args.value();
    else if (!a.empty() && a[0] == '-')
      return false;
    else
    {
      Source s;
      parsePathAndNumber(a, s.path, s.distance);
      sources.push_back(s);
    }
    return true;
  }

  void check() const
  {
    if (sources.empty())
      throw std::invalid_argument("no SOURCE:DISTANCE given");
  }
};

/// Decodes every image of every source and adds it to @p calibration, saying how much each gave
/// ("source 2 of 5, plane at 0.600 m: ...").
void addSources(const PlaneArgs& a, const sl_projector::Rig& rig, double epipolar_tolerance,
                PlaneCalibration& calibration)
{
  sl_decoder::Decoder decoder(rig, calibrationDecoderConfig(epipolar_tolerance));
  sl_decoder::DecodeResult result;
  for (size_t i = 0; i < a.sources.size(); ++i)
  {
    const Source& s = a.sources[i];
    const std::string progress = "source " + std::to_string(i + 1) + " of " + std::to_string(a.sources.size()) +
                                 ", plane at " + fixed(s.distance, 3) + " m: ";
    forEachImage(s, a.topic,
                 [&](const std::string& name, const cv::Mat& grey)
                 {
                   if (grey.cols != rig.camera.width || grey.rows != rig.camera.height)
                     throw CalibrationError(name + ": the image is " + std::to_string(grey.cols) + " x " +
                                            std::to_string(grey.rows) + " px, the rig's camera " +
                                            std::to_string(rig.camera.width) + " x " +
                                            std::to_string(rig.camera.height));
                   decoder.decode(grey, result);
                   const int n = calibration.addImage(s.distance, result, name);
                   std::cout << progress << name << ": " << n << " primitives" << std::endl;
                   if (n == 0)
                     std::cerr << "sl_calibrate_plane: warning: " << name
                               << ": no primitive decoded (projector off? plane not in view? wrong --rig?)\n";
                 });
  }
}

/// Calibrates and writes the residuals (if asked) and the calibration file.
void calibrate(const tool::CommonOptions& common, const PlaneArgs& a, bool&)
{
  const sl_projector::Rig rig = sl_projector::loadRig(common.rig_path);
  PlaneCalibration calibration(rig, common.planes);
  addSources(a, rig, common.epipolar_tolerance, calibration);
  const PlaneCalibrationResult res = calibration.fit();
  std::cout << "\n" << res.summary();
  if (!a.residuals_csv.empty())
  {
    std::ofstream csv(a.residuals_csv);
    if (!csv || !(csv << res.residualsCsv()))
      throw CalibrationError(a.residuals_csv + ": cannot write the residuals");
    std::cout << "per-primitive residuals: " << a.residuals_csv << "\n";
  }
  if (!a.residuals_png.empty())
  {
    writePlaneResidualPlot(a.residuals_png, res, cv::Size(rig.camera.width, rig.camera.height));
    std::cout << "residual plot: " << a.residuals_png << "\n";
  }
  sl_projector::saveRig(withTables(rig, res), common.out_path);
  std::cout << "wrote " << common.out_path << " (depth_tables: linear and rational, " << res.calibrated
            << " primitives)\n";
}
}  // namespace

int main(int argc, char** argv)
{
  return tool::run<PlaneArgs>("sl_calibrate_plane", kUsage, argc, argv, calibrate);
}
