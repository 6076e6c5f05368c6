#pragma once
/// @file collision.h
/// @brief Ground-truth collision of a simulated round robot with a scene: every object that reaches
/// into the robot's disc, in any direction, and the clearance to the nearest one (ROS-free).
///
/// Unlike computeContact() (contact.h), which models the bumper and so senses only its arc, this is
/// the truth for tests: a box behind the robot that the bumper cannot feel still collides.

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sl_sim/contact.h"
#include "sl_sim/scene.h"

namespace sl_sim
{

/// @brief What computeCollision() found for one robot pose.
struct CollisionReport
{
  bool colliding = false;          ///< some object lies inside the disc
  std::vector<int> objects;        ///< indices (scene order) of the objects inside the disc
  std::vector<std::string> names;  ///< their names, objectName()
  /// Horizontal gap between the disc's edge and the nearest object part within the heights, m;
  /// <= 0 inside the disc (-robot_radius when the object reaches the robot's axis); +inf when no
  /// object reaches into those heights.
  double min_clearance = std::numeric_limits<double>::infinity();
  int nearest_object = -1;   ///< index of that nearest object, -1 for none
  std::string nearest_name;  ///< its name, empty for none
};

/// @brief Name of object @p index of @p scene for messages: its `name` from the scene file, or
/// "<type> #<index>" (e.g. "box #3") when it has none.
std::string objectName(const Scene& scene, int index);

/**
 * @brief Horizontal distance from the z axis of a frame to the part of @p object between heights
 * @p z_min and @p z_max of that frame, m (0 when the part reaches the axis).
 *
 * Exact for every primitive: planes (infinite or rectangles) and boxes by clipping with the two
 * heights, cylinders of any orientation (closed form when upright, otherwise a convex search over
 * the height and the axis to below a nanometre).
 * @param object_in_frame the object's pose in the frame (e.g. robot_in_world.inverse() * object.pose)
 * @return +inf when no part of the object lies between the heights.
 */
double horizontalDistance(const SceneObject& object, const Eigen::Isometry3d& object_in_frame, double z_min,
                          double z_max);

/**
 * @brief Collision of the robot at @p robot_in_world (x forward, y left, z up, origin on the floor
 * at the robot's centre; e.g. tf base_footprint_true) with @p scene.
 *
 * The robot is the disc of @p settings.robot_radius around its z axis, from contact_min_height to
 * robot_height above its origin (the footprint of computeContact()). An object collides when any
 * part of it between those heights lies within the disc (clearance <= 0), in any direction. Objects
 * marked `floor` never collide and are not counted for the clearance.
 * @param[out] report filled; its buffers are reused from call to call.
 * @throws std::invalid_argument when @p settings are invalid (ContactSettings::validate()).
 */
void computeCollision(const Scene& scene, const Eigen::Isometry3d& robot_in_world, const ContactSettings& settings,
                      CollisionReport& report);

/// @brief computeCollision() returning a new report.
CollisionReport computeCollision(const Scene& scene, const Eigen::Isometry3d& robot_in_world,
                                 const ContactSettings& settings = ContactSettings());

}  // namespace sl_sim
