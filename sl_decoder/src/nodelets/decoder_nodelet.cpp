// The decoder nodelet: image_raw in, PointCloud2 in the target frame out. ROS plumbing only; the
// decoding is the sl_decoder core library.
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <string>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <opencv2/imgproc.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <boost/make_shared.hpp>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "sl_decoder/DecoderParamsConfig.h"
#include "sl_decoder/decoder.h"
#include "sl_decoder/ray_classifier.h"
#include "sl_msgs/ray_ends.h"
#include "sl_params/params.h"
#include "sl_rig/mono8.h"
#include "sl_rig/ros/rig_param.h"

namespace sl_decoder
{
// The core's ray states are the wire values of the ray_ends cloud.
static_assert(static_cast<int>(RayState::Decoded) == sl_msgs::ray_ends::DECODED, "RayState::Decoded");
static_assert(static_cast<int>(RayState::Floor) == sl_msgs::ray_ends::FLOOR, "RayState::Floor");
static_assert(static_cast<int>(RayState::Dark) == sl_msgs::ray_ends::DARK, "RayState::Dark");
static_assert(static_cast<int>(RayState::Lit) == sl_msgs::ray_ends::LIT, "RayState::Lit");
static_assert(static_cast<int>(RayState::Unseen) == sl_msgs::ray_ends::UNSEEN, "RayState::Unseen");

namespace
{
/// Node parameters that are not decoder tunables, read and validated in one place (the rig:
/// sl_projector::loadRigParam()).
struct NodeParams
{
  std::string target_frame = "platform_edge";
  std::string camera_frame;  // empty: the image's frame_id
  double tf_timeout = 0.0;
  bool organized = false;
  int queue_size = 2;
  bool rays = false;  // classify the rays even when nobody subscribes ray_ends
  DecoderConfig decoder;
  RayConfig ray;
};

/// Copies the reconfigurable tunables (cfg/DecoderParams.cfg) into @p d: at start and on every
/// reconfiguration, so the table and the decoder cannot drift apart.
void applyTunables(const DecoderParamsConfig& c, DecoderConfig& d)
{
  d.threshold_window = c.threshold_window | 1;  // keep it odd
  d.threshold_offset = c.threshold_offset;
  d.min_area = c.min_area;
  d.max_area = c.max_area;
  d.max_aspect = c.max_aspect;
  d.min_fill = c.min_fill;
  d.min_contrast = c.min_contrast;
  d.min_margin = c.min_margin;
  d.min_correlation = c.min_correlation;
  d.neighbour_along_min = c.neighbour_along_min;
  d.neighbour_along_max = c.neighbour_along_max;
  d.neighbour_across = c.neighbour_across;
  d.epipolar_tolerance = c.epipolar_tolerance;
  d.min_support = c.min_support;
  d.min_confidence = c.min_confidence;
  d.split_merged = c.split_merged;
}

/// The ray classifier's parameters (~rays, ~min_albedo, ...), checked by RayConfig::validate().
void readRayParams(const ros::NodeHandle& pnh, NodeParams& p)
{
  p.rays = sl_params::read(pnh, "rays", p.rays);
  RayConfig& r = p.ray;
  r.min_albedo = sl_params::read(pnh, "min_albedo", r.min_albedo);
  r.pattern_contrast_1m = sl_params::read(pnh, "pattern_contrast_1m", r.pattern_contrast_1m);
  r.light_fraction = sl_params::read(pnh, "light_fraction", r.light_fraction);
  r.noise_floor = sl_params::read(pnh, "noise_floor", r.noise_floor);
  r.max_range = sl_params::read(pnh, "ray_max_range", r.max_range);
  try
  {
    r.validate();
    if (r.max_range <= p.decoder.min_depth || r.max_range > p.decoder.max_depth)
      throw std::invalid_argument("max_range must be in (min_depth, max_depth] of the decoder");
  }
  catch (const std::invalid_argument& e)
  {
    const std::string what = e.what();
    // The classifier's max_range is the parameter ~ray_max_range.
    throw std::invalid_argument(what.rfind("max_range", 0) == 0 ? "~ray_" + what : "~" + what);
  }
}

NodeParams readParams(const ros::NodeHandle& pnh)
{
  NodeParams p;
  p.target_frame = sl_params::read(pnh, "target_frame", p.target_frame);
  if (p.target_frame.empty())
    throw std::invalid_argument("~target_frame must not be empty");
  p.camera_frame = sl_params::read(pnh, "camera_frame", p.camera_frame);
  p.tf_timeout = sl_params::read(pnh, "tf_timeout", p.tf_timeout);
  if (!std::isfinite(p.tf_timeout) || p.tf_timeout < 0.0 || p.tf_timeout > 5.0)
    throw std::invalid_argument("~tf_timeout must be in [0, 5] s");
  p.organized = sl_params::read(pnh, "organized", p.organized);
  p.queue_size = sl_params::read(pnh, "queue_size", p.queue_size);
  if (p.queue_size < 1)
    throw std::invalid_argument("~queue_size must be >= 1");
  DecoderConfig& d = p.decoder;
  d.min_depth = sl_params::read(pnh, "min_depth", d.min_depth);
  d.max_depth = sl_params::read(pnh, "max_depth", d.max_depth);
  d.nominal_depth = sl_params::read(pnh, "nominal_depth", d.nominal_depth);
  // The tunables: cfg/DecoderParams.cfg is their one table (defaults, ranges, descriptions).
  DecoderParamsConfig tunables = DecoderParamsConfig::__getDefault__();
  sl_params::checkReconfigureTypes<DecoderParamsConfig>(pnh);
  ros::NodeHandle server(pnh);
  tunables.__fromServer__(server);
  applyTunables(tunables, d);
  d.depth_mode = parseDepthMode(sl_params::read(pnh, "depth_mode", std::string(depthModeName(d.depth_mode))));
  try
  {
    d.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  readRayParams(pnh, p);
  return p;
}
}  // namespace

/**
 * Subscribes `image_raw` (only while `points`, `ray_ends`, `depth/image_raw` or `debug_image` has a
 * subscriber, or `~rays` is true) and publishes the decoded primitives and the per-ray outcomes.
 */
class DecoderNodelet : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try
    {
      rig_ = sl_projector::loadRigParam(pnh).rig;
      params_ = readParams(pnh);
      decoder_.reset(new Decoder(rig_, params_.decoder));
      rays_.reset(new RayClassifier(rig_, params_.decoder, params_.ray));
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }

    tf_buffer_.reset(new tf2_ros::Buffer(ros::Duration(10.0)));
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh));
    it_.reset(new image_transport::ImageTransport(nh));

    const ros::SubscriberStatusCallback connect = [this](const ros::SingleSubscriberPublisher&)
    { updateSubscription(); };
    const image_transport::SubscriberStatusCallback image_connect =
        [this](const image_transport::SingleSubscriberPublisher&) { updateSubscription(); };
    std::lock_guard<std::mutex> lock(connect_mutex_);
    points_pub_ = nh.advertise<sensor_msgs::PointCloud2>("points", 2, connect, connect);
    rays_pub_ = nh.advertise<sensor_msgs::PointCloud2>("ray_ends", 2, connect, connect);
    depth_pub_ = it_->advertise("depth/image_raw", 2, image_connect, image_connect);
    debug_pub_ = it_->advertise("debug_image", 1, image_connect, image_connect);

    reconfigure_.reset(new dynamic_reconfigure::Server<DecoderConfigMsg>(reconfigure_mutex_, pnh));
    reconfigure_->setCallback([this](DecoderConfigMsg& c, uint32_t) { reconfigure(c); });

    diagnostics_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    diagnostics_->setHardwareID("sl_decoder");
    diagnostics_->add("decoding", this, &DecoderNodelet::diagnose);
    diagnostics_timer_ =
        nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnostics_->update(); });
    NODELET_INFO("decoder ready: %d x %d camera, %d x %d pattern, depth %s, points in %s", rig_.camera.width,
                 rig_.camera.height, rig_.pattern.rows, rig_.pattern.cols, depthModeName(params_.decoder.depth_mode),
                 params_.target_frame.c_str());
  }

  using DecoderConfigMsg = sl_decoder::DecoderParamsConfig;  // generated by dynamic_reconfigure

  void reconfigure(const DecoderConfigMsg& c)
  {
    sl_decoder::DecoderConfig d;
    {
      std::lock_guard<std::mutex> lock(decoder_mutex_);
      d = decoder_->config();
    }
    applyTunables(c, d);
    try
    {
      std::unique_ptr<Decoder> fresh(new Decoder(rig_, d));
      std::lock_guard<std::mutex> lock(decoder_mutex_);
      decoder_ = std::move(fresh);
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("rejected reconfiguration, keeping the previous settings: %s", e.what());
    }
  }

  void updateSubscription()
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const bool wanted = points_pub_.getNumSubscribers() > 0 || depth_pub_.getNumSubscribers() > 0 ||
                        debug_pub_.getNumSubscribers() > 0 || rays_pub_.getNumSubscribers() > 0 || params_.rays;
    if (wanted && !image_sub_)
    {
      image_sub_ =
          it_->subscribe("image_raw", static_cast<uint32_t>(params_.queue_size), &DecoderNodelet::onImage, this);
      NODELET_DEBUG("subscribed to %s", image_sub_.getTopic().c_str());
    }
    else if (!wanted && image_sub_)
    {
      image_sub_.shutdown();
      NODELET_DEBUG("nobody listens: unsubscribed from image_raw");
    }
  }

  void onImage(const sensor_msgs::ImageConstPtr& msg)
  {
    cv::Mat mono;
    try
    {
      bool converted = false;
      const cv_bridge::CvImageConstPtr cv = cv_bridge::toCvShare(msg);
      mono = sl_rig::toMono8(cv->image, msg->encoding, converted);
      if (converted && !warned_conversion_)
      {
        NODELET_WARN("converting %s images to mono8 (publish mono8 to avoid the cost)", msg->encoding.c_str());
        warned_conversion_ = true;
      }
    }
    catch (const std::exception& e)
    {
      ++rejected_;
      NODELET_ERROR_THROTTLE(5.0, "dropping image: %s", e.what());
      return;
    }

    DecodeResult& result = result_;
    {
      std::lock_guard<std::mutex> lock(decoder_mutex_);
      if (mono.cols != rig_.camera.width || mono.rows != rig_.camera.height)
      {
        ++rejected_;
        NODELET_ERROR_THROTTLE(5.0, "dropping %d x %d image: the calibration's camera is %d x %d", mono.cols, mono.rows,
                               rig_.camera.width, rig_.camera.height);
        return;
      }
      decoder_->decode(mono, result);
    }
    {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      last_blobs_ = static_cast<int>(result.blobs.size());
      last_decoded_ = result.decoded;
      last_valid_ = result.valid;
      last_ms_ = result.times.total;
      ++frames_;
    }

    const bool rays = params_.rays || rays_pub_.getNumSubscribers() > 0;
    const bool points = points_pub_.getNumSubscribers() > 0;
    Eigen::Isometry3d to_target;
    const bool located = (points || rays) && lookupTarget(msg->header, to_target);
    // The points first: the obstacle node's stop check runs on them and must not wait for the rays.
    if (located && points)
      publishCloud(msg->header, result, to_target);
    if (rays)
    {
      rays_->classify(mono, result, outcomes_);
      {
        std::lock_guard<std::mutex> lock(stats_mutex_);
        last_rays_ = rays_->lastCounts();
      }
      if (located)
        publishRays(msg->header, to_target);  // same frame and stamp as the points
    }
    if (depth_pub_.getNumSubscribers() > 0)
      publishDepth(msg->header, result);
    if (debug_pub_.getNumSubscribers() > 0)
      publishDebug(msg->header, mono, result);
  }

  /// The camera -> target_frame transform at the image time; false (with a throttled warning) when
  /// there is none: then nothing is published rather than wrong points. Never waits unless
  /// ~tf_timeout > 0: when the transform at the image time is not there yet, the newest one is used
  /// (exact for the static mount; for a moving target frame its age is in the diagnostics).
  bool lookupTarget(const std_msgs::Header& image_header, Eigen::Isometry3d& to_target)
  {
    const std::string source = params_.camera_frame.empty() ? image_header.frame_id : params_.camera_frame;
    if (source.empty())
    {
      NODELET_WARN_THROTTLE(5.0, "image has no frame_id and ~camera_frame is not set: no points published");
      return false;
    }
    try
    {
      if (params_.tf_timeout > 0.0 || tf_buffer_->canTransform(params_.target_frame, source, image_header.stamp))
        to_target = tf2::transformToEigen(tf_buffer_->lookupTransform(params_.target_frame, source, image_header.stamp,
                                                                      ros::Duration(params_.tf_timeout)));
      else
      {
        const geometry_msgs::TransformStamped t =
            tf_buffer_->lookupTransform(params_.target_frame, source, ros::Time(0));
        to_target = tf2::transformToEigen(t);
        ++tf_latest_;
        tf_age_ = t.header.stamp.isZero() ? 0.0 : (image_header.stamp - t.header.stamp).toSec();
      }
    }
    catch (const tf2::TransformException& e)
    {
      ++tf_failures_;
      NODELET_WARN_THROTTLE(5.0, "no transform %s -> %s, no points published: %s", source.c_str(),
                            params_.target_frame.c_str(), e.what());
      return false;
    }
    return true;
  }

  void publishCloud(const std_msgs::Header& image_header, const DecodeResult& result,
                    const Eigen::Isometry3d& to_target)
  {
    // Published by pointer: nodelets in the same manager receive it without a copy.
    const sensor_msgs::PointCloud2Ptr cloud_ptr = boost::make_shared<sensor_msgs::PointCloud2>();
    sensor_msgs::PointCloud2& cloud = *cloud_ptr;
    cloud.header.stamp = image_header.stamp;
    cloud.header.frame_id = params_.target_frame;
    sensor_msgs::PointCloud2Modifier modifier(cloud);
    // sx, sy, sz: the projector centre, where the free part of every decoded ray starts.
    using sensor_msgs::PointField;
    modifier.setPointCloud2Fields(11, "x", 1, PointField::FLOAT32, "y", 1, PointField::FLOAT32, "z", 1,
                                  PointField::FLOAT32, "confidence", 1, PointField::FLOAT32, "row", 1,
                                  PointField::UINT16, "col", 1, PointField::UINT16, "u", 1, PointField::FLOAT32, "v", 1,
                                  PointField::FLOAT32, "sx", 1, PointField::FLOAT32, "sy", 1, PointField::FLOAT32, "sz",
                                  1, PointField::FLOAT32);
    const Eigen::Vector3d centre = to_target * rig_.projectorCentre();
    const int rows = rig_.pattern.rows, cols = rig_.pattern.cols;
    if (params_.organized)
    {
      // One point per pattern primitive, NaN where it was not decoded: rows x cols, row-major.
      modifier.resize(static_cast<size_t>(rows * cols));
      cloud.height = static_cast<uint32_t>(rows);
      cloud.width = static_cast<uint32_t>(cols);
      cloud.row_step = cloud.width * cloud.point_step;
      cloud.is_dense = false;
      const float nan = std::numeric_limits<float>::quiet_NaN();
      sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), cf(cloud, "confidence"), u(cloud, "u"), sx(cloud, "sx");
      sensor_msgs::PointCloud2Iterator<uint16_t> r(cloud, "row");
      for (int i = 0; i < rows * cols; ++i, ++x, ++cf, ++u, ++r, ++sx)
      {
        x[0] = x[1] = x[2] = nan;
        sx[0] = sx[1] = sx[2] = nan;
        cf[0] = 0.f;
        u[0] = u[1] = nan;
        r[0] = static_cast<uint16_t>(i / cols);
        r[1] = static_cast<uint16_t>(i % cols);
      }
    }
    else
    {
      modifier.resize(static_cast<size_t>(result.valid));
      cloud.is_dense = true;
    }
    sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), cf(cloud, "confidence"), u(cloud, "u"), sx(cloud, "sx");
    sensor_msgs::PointCloud2Iterator<uint16_t> r(cloud, "row");
    size_t k = 0;
    for (const Blob& b : result.blobs)
    {
      if (!b.valid)
        continue;
      const size_t index = params_.organized ? static_cast<size_t>(b.row * cols + b.col) : k++;
      const Eigen::Vector3d p = to_target * Eigen::Vector3d(b.x, b.y, b.z);
      sensor_msgs::PointCloud2Iterator<float> xi = x + static_cast<int>(index);
      sensor_msgs::PointCloud2Iterator<float> ci = cf + static_cast<int>(index);
      sensor_msgs::PointCloud2Iterator<float> ui = u + static_cast<int>(index);
      sensor_msgs::PointCloud2Iterator<uint16_t> ri = r + static_cast<int>(index);
      xi[0] = static_cast<float>(p.x());
      xi[1] = static_cast<float>(p.y());
      xi[2] = static_cast<float>(p.z());
      ci[0] = b.confidence;
      ri[0] = static_cast<uint16_t>(b.row);
      ri[1] = static_cast<uint16_t>(b.col);
      ui[0] = b.u;
      ui[1] = b.v;
      sensor_msgs::PointCloud2Iterator<float> si = sx + static_cast<int>(index);
      si[0] = static_cast<float>(centre.x());
      si[1] = static_cast<float>(centre.y());
      si[2] = static_cast<float>(centre.z());
    }
    points_pub_.publish(cloud_ptr);
  }

  /// ray_ends: one point per primitive that was not decoded (floor, dark, lit, unseen), see the README.
  void publishRays(const std_msgs::Header& image_header, const Eigen::Isometry3d& to_target)
  {
    // Published by pointer: nodelets in the same manager receive it without a copy.
    const sensor_msgs::PointCloud2Ptr cloud_ptr = boost::make_shared<sensor_msgs::PointCloud2>();
    sensor_msgs::PointCloud2& cloud = *cloud_ptr;
    cloud.header.stamp = image_header.stamp;
    cloud.header.frame_id = params_.target_frame;
    // The layout of sl_msgs/ray_ends.h: 6 floats, the state, the pattern row and column.
    namespace re = sl_msgs::ray_ends;
    auto field = [&cloud](const char* name, uint32_t offset, uint8_t type)
    {
      sensor_msgs::PointField f;
      f.name = name;
      f.offset = offset;
      f.datatype = type;
      f.count = 1;
      cloud.fields.push_back(f);
    };
    const char* names[6] = { "x", "y", "z", "sx", "sy", "sz" };
    for (uint32_t k = 0; k < 6; ++k)
      field(names[k], 4 * k, sensor_msgs::PointField::FLOAT32);
    field("state", re::kStateOffset, sensor_msgs::PointField::UINT8);
    field("row", re::kRowOffset, sensor_msgs::PointField::UINT16);
    field("col", re::kColOffset, sensor_msgs::PointField::UINT16);
    cloud.point_step = re::kPointStep;
    const size_t n = outcomes_.size();
    const size_t count = n - static_cast<size_t>(rays_->lastCount(RayState::Decoded));
    cloud.height = 1;
    cloud.width = static_cast<uint32_t>(count);
    cloud.row_step = cloud.width * cloud.point_step;
    cloud.is_dense = false;  // unseen rays are NaN
    cloud.data.assign(count * cloud.point_step, 0);
    uint8_t* out = cloud.data.data();
    const int cols = rig_.pattern.cols;
    for (size_t i = 0; i < n; ++i)
    {
      const RayOutcome& o = outcomes_[i];
      if (o.state == RayState::Decoded)
        continue;
      const Eigen::Vector3f end = (to_target * o.end.cast<double>()).cast<float>();
      const Eigen::Vector3f start = (to_target * o.start.cast<double>()).cast<float>();
      re::Point point{};
      point.x = end.x();
      point.y = end.y();
      point.z = end.z();
      point.sx = start.x();
      point.sy = start.y();
      point.sz = start.z();
      point.state = static_cast<uint8_t>(o.state);
      point.row = static_cast<uint16_t>(i / static_cast<size_t>(cols));
      point.col = static_cast<uint16_t>(i % static_cast<size_t>(cols));
      std::memcpy(out, &point, sizeof(point));
      out += cloud.point_step;
    }
    rays_pub_.publish(cloud_ptr);
  }

  void publishDepth(const std_msgs::Header& header, const DecodeResult& result)
  {
    // REP 118: 32FC1 metres in the camera frame, NaN where there is no measurement.
    cv_bridge::CvImage depth(
        header, sensor_msgs::image_encodings::TYPE_32FC1,
        cv::Mat(rig_.camera.height, rig_.camera.width, CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN())));
    for (const Blob& b : result.blobs)
    {
      if (!b.valid)
        continue;
      const int x = static_cast<int>(std::lround(b.u)), y = static_cast<int>(std::lround(b.v));
      if (x >= 0 && y >= 0 && x < depth.image.cols && y < depth.image.rows)
        depth.image.at<float>(y, x) = b.z;
    }
    depth_pub_.publish(depth.toImageMsg());
  }

  void publishDebug(const std_msgs::Header& header, const cv::Mat& mono, const DecodeResult& result)
  {
    cv_bridge::CvImage debug(header, sensor_msgs::image_encodings::BGR8, cv::Mat());
    cv::cvtColor(mono, debug.image, cv::COLOR_GRAY2BGR);
    static const cv::Scalar kShapeColour[5] = { cv::Scalar(128, 128, 128), cv::Scalar(255, 80, 80),
                                                cv::Scalar(80, 220, 80), cv::Scalar(60, 60, 255),
                                                cv::Scalar(0, 220, 255) };
    for (const Blob& b : result.blobs)
    {
      const cv::Scalar& colour = kShapeColour[b.shape];
      cv::rectangle(debug.image, cv::Rect(b.x0, b.y0, b.width(), b.height()), colour, 1);
      if (b.decoded())
      {
        cv::circle(debug.image, cv::Point(static_cast<int>(b.u), static_cast<int>(b.v)), 2, cv::Scalar(255, 255, 255),
                   cv::FILLED);
        if (b.col % 4 == 0)  // every fourth column, or the labels cover the image
          cv::putText(debug.image, std::to_string(b.row) + "," + std::to_string(b.col), cv::Point(b.x0, b.y0 - 2),
                      cv::FONT_HERSHEY_PLAIN, 0.6, cv::Scalar(255, 255, 255), 1);
      }
    }
    debug_pub_.publish(debug.toImageMsg());
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status)
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    const double valid_fraction = last_blobs_ > 0 ? static_cast<double>(last_valid_) / last_blobs_ : 0.0;
    if (frames_ == 0)
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, "no image decoded yet (idle until someone subscribes)");
    else if (last_valid_ == 0)
      status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no points in the last image");
    else
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, "decoding");
    status.add("frames", frames_);
    status.add("blobs", last_blobs_);
    status.add("decoded", last_decoded_);
    status.add("valid points", last_valid_);
    status.add("valid fraction of blobs", valid_fraction);
    status.add("processing time (ms)", last_ms_);
    status.add("rejected images", rejected_);
    status.add("tf failures", tf_failures_);
    status.add("tf newest used (not yet at the image time)", tf_latest_);
    status.add("tf age of the newest used, s", tf_age_);
    for (int k = 1; k < kRayStates; ++k)  // the ray outcomes of the last classified frame
      status.add(std::string("rays ") + toString(static_cast<RayState>(k)), last_rays_[static_cast<size_t>(k)]);
  }

  NodeParams params_;
  sl_projector::Rig rig_;
  std::mutex decoder_mutex_;
  std::unique_ptr<Decoder> decoder_;
  DecodeResult result_;
  std::unique_ptr<RayClassifier> rays_;
  std::vector<RayOutcome> outcomes_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  std::mutex connect_mutex_;
  image_transport::Subscriber image_sub_;
  ros::Publisher points_pub_, rays_pub_;
  image_transport::Publisher depth_pub_, debug_pub_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<DecoderConfigMsg>> reconfigure_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_;
  std::mutex stats_mutex_;
  int last_blobs_ = 0, last_decoded_ = 0, last_valid_ = 0;
  std::array<int, kRayStates> last_rays_{};
  double last_ms_ = 0.0;
  long frames_ = 0, rejected_ = 0, tf_failures_ = 0, tf_latest_ = 0;
  double tf_age_ = 0.0;
  bool warned_conversion_ = false;
};

}  // namespace sl_decoder

PLUGINLIB_EXPORT_CLASS(sl_decoder::DecoderNodelet, nodelet::Nodelet)
