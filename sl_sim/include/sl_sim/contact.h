#pragma once
/// @file contact.h
/// @brief Bumper contact of a simulated round robot with a scene (ROS-free).

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "sl_sim/scene.h"

namespace sl_sim
{

/// @brief Bump bits as in the Create Open Interface sensor packet 7.
enum BumpBits : uint8_t
{
  kBumpRight = 1,  ///< bit 0: right bumper
  kBumpLeft = 2    ///< bit 1: left bumper
};

/**
 * @brief The robot's footprint for contact: a vertical cylinder around the robot frame's z axis.
 */
struct ContactSettings
{
  double robot_radius = 0.1675;         ///< footprint radius, m (the Create: 335 mm diameter)
  double robot_height = 0.10;           ///< top of the part that can touch (body and rig platform), m
  double contact_min_height = 0.01;     ///< objects whose top is lower (a flat cable) are driven over, m
  double both_half_angle = 0.349066;    ///< contacts within +-this of straight ahead press both bumpers (20 deg), rad
  double bumper_half_angle = 1.570796;  ///< the bumper covers +-this around the heading (90 deg), rad

  /// @brief Checks the values. @throws std::invalid_argument naming the field.
  void validate() const;
};

/// @brief One contact found: the direction of the touching surface seen from the robot's centre.
struct ContactPoint
{
  double angle = 0.0;     ///< rad, 0 straight ahead, positive to the left
  double distance = 0.0;  ///< horizontal distance from the robot's axis, m
  int object = -1;        ///< index in the scene
};

/**
 * @brief Bumper bits of a robot at @p robot_in_world (x forward, y left, z up, origin on the floor
 * at the robot's centre; e.g. tf base_footprint_true).
 *
 * An object touches the robot when part of it lies within the footprint cylinder (radius
 * robot_radius, from contact_min_height to robot_height above the robot frame's origin). Objects
 * marked `floor` and objects whose top is below contact_min_height never touch. The surface is
 * probed by horizontal rays from the robot's axis every degree over the bumper's arc at four
 * heights; a robot whose axis lies inside a solid touches it straight ahead. A contact at angle a
 * sets both bits when |a| <= both_half_angle, else the left bit (a > 0) or the right bit (a < 0).
 * Contacts behind the bumper's arc set no bit.
 *
 * @param[out] points when not null, receives every probe that touched.
 * @return kBumpRight | kBumpLeft bits.
 */
uint8_t computeContact(const Scene& scene, const Eigen::Isometry3d& robot_in_world,
                       const ContactSettings& settings = ContactSettings(),
                       std::vector<ContactPoint>* points = nullptr);

}  // namespace sl_sim
