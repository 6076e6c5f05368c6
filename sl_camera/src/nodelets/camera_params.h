// Parameters of the sl_camera/camera nodelet: read, typed and range-checked in one place.
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "sl_camera/camera/camera_config.h"

namespace sl_camera
{
/// Everything the camera nodelet is configured with.
struct CameraParams
{
  CameraConfig camera;
  std::string frame_id = "camera_optical_frame";
  std::string camera_name = "camera";
  std::string camera_info_url;
  std::string rig_file;                  ///< rig whose camera image size the camera must deliver ("": none)
  int rig_width = 0;                     ///< every frame's width, px (0: any; no rig file, or the player)
  int rig_height = 0;                    ///< every frame's height, px (0: any)
  bool player_ignores_settings = false;  ///< width/height/exposure/gain were set (not default) for the player
  bool offsets_ignored = false;          ///< offset_x/offset_y set for a back-end without region offsets
};

/// Reads every private parameter of @p pnh (and the rig file's image size, when one is given).
/// @throws std::invalid_argument "~<name> ..." naming the first invalid parameter.
CameraParams readCameraParams(const ros::NodeHandle& pnh);

/// Why no calibration was loaded for @p p: no ~camera_info_url and no default file, or the URL's file.
std::string uncalibratedReason(const CameraParams& p);
}  // namespace sl_camera
