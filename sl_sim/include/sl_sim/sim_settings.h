#pragma once
/// @file sim_settings.h
/// @brief Image-formation parameters of the projector-camera simulator (ROS-free).

#include <string>
#include <vector>

namespace sl_sim
{

/**
 * @brief Every image-formation parameter of the simulator, with realistic defaults.
 *
 * Radiometric units: the sensor's full scale (saturation, 255 DN before gamma) is 1.0 at
 * `exposure` = 1. `projector_power` = 1 means that a full-white projector pixel on a white
 * (albedo 1) surface facing the projector at `projector_focus_distance` fills the sensor exactly.
 * With the defaults a white plane (albedo 0.8) at 700 mm shows the pattern at about 200 DN on a
 * background of about 15 DN.
 *
 * Each field is also a ROS parameter of the sim_camera nodelet and a `--set name=value` option of
 * sl_render under the same name (see simSettingsInfo()).
 */
struct SimSettings
{
  // Light.
  /// Irradiance of a full-white projector pixel at projector_focus_distance, normal incidence
  /// (falls with 1/distance^2 and the cosine of the incidence angle).
  double projector_power = 1.0;
  /// Irradiance of a black projector pixel relative to a white one (a DLP's finite contrast).
  double projector_black_level = 0.02;
  /// Irradiance at the corners of the projector frame relative to its centre (lens falloff).
  double projector_vignetting = 0.85;
  /// Ambient irradiance (everywhere, no shadows), in units of projector_power.
  double ambient = 0.05;

  // Optics. The lenses' focus distance, f-number and pixel pitch are the rig's (LensOptics, rig
  // file keys camera.* and projector.*), so the decoder expects the blur the simulator renders;
  // a value > 0 here overrides the rig's (0: the rig's).
  /// Projector focus distance (along its optical axis), m; 0: the rig's.
  double projector_focus_distance = 0.0;
  /// Projector lens f-number (aperture diameter = focal length / f-number); 0: the rig's.
  double projector_f_number = 0.0;
  /// Projector mirror pitch, m (focal length = fx * pitch); 0: the rig's.
  double projector_pixel_size = 0.0;
  /// Blur of the projector at focus (Gaussian sigma), projector px.
  double projector_base_blur = 0.3;
  /// Camera focus distance (depth along the optical axis), m; 0: the rig's.
  double camera_focus_distance = 0.0;
  /// Camera lens f-number; 0: the rig's.
  double camera_f_number = 0.0;
  /// Camera pixel pitch, m; 0: the rig's.
  double camera_pixel_size = 0.0;
  /// Blur of the camera at focus (Gaussian sigma), camera px.
  double camera_base_blur = 0.3;
  /// Factor on both lenses' defocus blur: optics unlike what the rig file says (1: as it says).
  double defocus_scale = 1.0;
  /// Thin-lens defocus blur of projector and camera away from their focus distances.
  bool defocus = true;
  /// The projector's shadows: a point the projector cannot see (an object between them) gets no
  /// pattern (false: every point facing the projector is lit, as if occluders were transparent).
  bool shadows = true;
  /// Projector irradiance falls with the square of the distance and the cosine of the incidence
  /// angle (false: the irradiance at the focus distance and normal incidence everywhere).
  bool irradiance_falloff = true;
  /// Camera samples per pixel on object, face, shadow and texture edges: 1 (off), 4 (the centre and
  /// three rays 0.4 px from it, 120 degrees apart) or 16 (a 4 x 4 grid). Elsewhere one ray per
  /// pixel; the pattern is pre-filtered by its footprint instead.
  int antialias = 4;
  /// Illumination at the image corners relative to the centre (lens vignetting, 1 = none).
  double vignetting = 0.7;
  /// Fraction of the light the lens scatters into a wide halo (veiling glare, Gaussian sigma
  /// 10 px): bright highlights spill into their surroundings.
  double glare = 0.01;

  // Sensor.
  /// Overall gain from scene radiance to the sensor's full scale.
  double exposure = 1.0;
  /// Electrons at full scale: shot noise variance = signal / full_well (signal in full-scale units).
  double full_well = 6000.0;
  /// Read noise, DN (8-bit output scale, before gamma).
  double read_noise = 1.5;
  /// Shot and read noise on (false: noise-free images).
  bool noise = true;
  /// Output = 255 * signal^(1/gamma): 1 is the linear response of machine-vision cameras.
  double gamma = 1.0;

  /**
   * @brief Checks every field.
   * @throws std::invalid_argument whose message starts with the field's name.
   */
  void validate() const;
};

/// @brief Description of one SimSettings field.
struct SimSettingInfo
{
  /// @brief Field kind.
  enum class Kind
  {
    Double,
    Int,
    Bool
  };
  std::string name;         ///< field, ROS parameter and sl_render --set name
  Kind kind;                ///< value type
  std::string unit;         ///< unit ("" when none)
  std::string description;  ///< one line
};

/// @brief All SimSettings fields in declaration order.
const std::vector<SimSettingInfo>& simSettingsInfo();

/**
 * @brief Sets a field by name (bools: 0 = false, otherwise true; ints: rounded).
 * @throws std::invalid_argument for an unknown name.
 */
void setSimSetting(SimSettings& settings, const std::string& name, double value);

/// @brief Reads a field by name as a double. @throws std::invalid_argument for an unknown name.
double getSimSetting(const SimSettings& settings, const std::string& name);

}  // namespace sl_sim
