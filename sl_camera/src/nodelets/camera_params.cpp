#include "camera_params.h"

#include <cctype>
#include <stdexcept>

#include "sl_params/params.h"
#include "sl_rig/rig.h"

namespace sl_camera
{
namespace
{
/// `device` may be given as a number in a launch file ("0" becomes an int parameter).
std::string deviceParam(const ros::NodeHandle& pnh)
{
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam("device", v))
    return std::string();
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string>(v);
    case XmlRpc::XmlRpcValue::TypeInt:
      return std::to_string(static_cast<int>(v));
    default:
      throw std::invalid_argument("~device must be a string (path, index or camera id)");
  }
}

/// `socket_buffer` and `packet_size`: "auto" (or 0) or a number of bytes.
int autoOrBytesParam(const ros::NodeHandle& pnh, const std::string& name)
{
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam(name, v))
    return 0;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    return static_cast<int>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeString)
  {
    const std::string text = static_cast<std::string>(v);
    if (text == "auto")
      return 0;
    try
    {
      size_t used = 0;
      const long bytes = std::stol(text, &used);
      if (used == text.size() && bytes >= 0 && bytes <= (1L << 30))
        return static_cast<int>(bytes);
    }
    catch (const std::exception&)
    {
      // reported below
    }
  }
  throw std::invalid_argument("~" + name + " must be auto or a number of bytes");
}

/// The rig file's camera image size for @p c (the player keeps the size of its recordings).
void applyRigFile(const std::string& rig_file, CameraConfig& c)
{
  if (rig_file.empty())
    return;
  // The decoder triangulates with this rig: a camera image of another size cannot be decoded.
  sl_projector::Rig rig;
  try
  {
    rig = sl_projector::loadRig(rig_file);
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument(std::string("calibration_file: ") + e.what());
  }
  if (c.backend != CameraBackend::Player)
    c.applyRigSize(rig.camera.width, rig.camera.height, rig_file);
}

/// The device, its settings and its transport; the image size reconciled with the rig file's.
void readDeviceParams(const ros::NodeHandle& pnh, CameraParams& p)
{
  CameraConfig& c = p.camera;
  try
  {
    c.backend = parseCameraBackend(sl_params::read<std::string>(pnh, "backend", "v4l2"));
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  c.device = deviceParam(pnh);
  c.settings.width = sl_params::read(pnh, "width", c.settings.width);
  c.settings.height = sl_params::read(pnh, "height", c.settings.height);
  c.settings.rate = sl_params::read(pnh, "rate", c.settings.rate);
  c.settings.exposure = sl_params::read(pnh, "exposure", c.settings.exposure);
  c.settings.gain = sl_params::read(pnh, "gain", c.settings.gain);
  c.loop = sl_params::read(pnh, "loop", c.loop);
  c.settings.offset_x = sl_params::read(pnh, "offset_x", c.settings.offset_x);
  c.settings.offset_y = sl_params::read(pnh, "offset_y", c.settings.offset_y);
  c.reconnect_max_backoff = sl_params::read(pnh, "reconnect_max_backoff", c.reconnect_max_backoff);
  c.stall_timeout = sl_params::read(pnh, "stall_timeout", c.stall_timeout);
  try
  {
    c.aravis.packet_socket = parsePacketSocketMode(sl_params::read<std::string>(pnh, "packet_socket", "auto"));
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  c.aravis.socket_buffer = autoOrBytesParam(pnh, "socket_buffer");
  c.aravis.packet_size = autoOrBytesParam(pnh, "packet_size");
  // One name for the rig file across the nodelets; ~rig_file is the deprecated former one.
  sl_params::readIfSetRenamed(pnh, "calibration_file", "rig_file", p.rig_file);
  try
  {
    c.validate();
    applyRigFile(p.rig_file, c);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  if (!p.rig_file.empty() && c.backend != CameraBackend::Player)
  {
    p.rig_width = c.settings.width;
    p.rig_height = c.settings.height;
  }
  p.offsets_ignored = c.backend != CameraBackend::Aravis && (c.settings.offset_x >= 0 || c.settings.offset_y >= 0);
  p.player_ignores_settings =
      c.backend == CameraBackend::Player &&
      (c.settings.width != 0 || c.settings.height != 0 || c.settings.exposure > 0.0 || c.settings.gain >= 0.0);
}
}  // namespace

CameraParams readCameraParams(const ros::NodeHandle& pnh)
{
  CameraParams p;
  readDeviceParams(pnh, p);

  p.frame_id = sl_params::read(pnh, "frame_id", p.frame_id);
  if (p.frame_id.empty())
    throw std::invalid_argument("~frame_id must not be empty");
  p.camera_name = sl_params::read(pnh, "camera_name", p.camera_name);
  if (p.camera_name.empty())
    throw std::invalid_argument("~camera_name must not be empty");
  for (char ch : p.camera_name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_')
      throw std::invalid_argument("~camera_name must contain only letters, digits and '_', got '" + p.camera_name +
                                  "'");
  p.camera_info_url = sl_params::read(pnh, "camera_info_url", p.camera_info_url);
  const std::string& url = p.camera_info_url;
  if (!url.empty() && url.rfind("file://", 0) != 0 && url.rfind("package://", 0) != 0)
    throw std::invalid_argument("~camera_info_url must be empty, file:///path.yaml or package://pkg/path.yaml, got '" +
                                url + "'");
  return p;
}

std::string uncalibratedReason(const CameraParams& p)
{
  return p.camera_info_url.empty()
             ? "~camera_info_url is empty and there is no ~/.ros/camera_info/" + p.camera_name + ".yaml"
             : "~camera_info_url '" + p.camera_info_url + "' could not be loaded";
}
}  // namespace sl_camera
