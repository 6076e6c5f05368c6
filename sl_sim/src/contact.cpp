// Bumper contact: horizontal probe rays from the robot's axis against the scene's obstacles.
#include "sl_sim/contact.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry.h"

namespace sl_sim
{

void ContactSettings::validate() const
{
  auto require = [](bool ok, const std::string& msg)
  {
    if (!ok)
      throw std::invalid_argument(msg);
  };
  require(std::isfinite(robot_radius) && robot_radius > 0.0 && robot_radius < 10.0,
          "robot_radius: must be in (0, 10) m");
  require(std::isfinite(contact_min_height) && contact_min_height >= 0.0, "contact_min_height: must be >= 0 m");
  require(std::isfinite(robot_height) && robot_height > contact_min_height,
          "robot_height: must be above contact_min_height");
  require(std::isfinite(both_half_angle) && both_half_angle >= 0.0 && both_half_angle <= M_PI,
          "both_half_angle: must be in 0..pi rad");
  require(std::isfinite(bumper_half_angle) && bumper_half_angle >= both_half_angle && bumper_half_angle <= M_PI,
          "bumper_half_angle: must be in both_half_angle..pi rad");
}

namespace
{
bool insideSolid(const sim::PreparedObject<double>& o, const Eigen::Vector3d& p)
{
  if (o.type == ObjectType::Plane)
    return false;
  const Eigen::Vector3d l = o.toLocal(p);
  if (o.type == ObjectType::Box)
    return (l.cwiseAbs().array() <= o.half.array()).all();
  return std::abs(l.z()) <= o.half.z() && l.x() * l.x() + l.y() * l.y() <= o.half.x() * o.half.x();
}
}  // namespace

uint8_t computeContact(const Scene& scene, const Eigen::Isometry3d& robot_in_world, const ContactSettings& s,
                       std::vector<ContactPoint>* points)
{
  if (points)
    points->clear();
  constexpr int kHeights = 4;
  const double step = M_PI / 180.0;
  const int n_angles = static_cast<int>(std::floor(s.bumper_half_angle / step + 1e-9));
  uint8_t bits = 0;
  auto record = [&](double angle, double distance, int object)
  {
    if (std::abs(angle) <= s.both_half_angle + 1e-9)
      bits |= kBumpLeft | kBumpRight;
    else
      bits |= angle > 0.0 ? kBumpLeft : kBumpRight;
    if (points)
      points->push_back(ContactPoint{ angle, distance, object });
  };
  for (size_t i = 0; i < scene.objects.size(); ++i)
  {
    const SceneObject& obj = scene.objects[i];
    if (obj.floor)
      continue;
    // The object's top, measured in the robot frame (the world's z when the robot stands on the floor).
    sim::PreparedObject<double> o;
    o.set(obj, robot_in_world.inverse() * obj.pose, static_cast<int>(i));
    const double top = o.support(Eigen::Vector3d::UnitZ());
    const double bottom = -o.support(-Eigen::Vector3d::UnitZ());
    if (top < s.contact_min_height || bottom > s.robot_height)
      continue;
    bool touched = false;
    for (int h = 0; h < kHeights && !touched; ++h)
    {
      const double z = s.contact_min_height + (s.robot_height - s.contact_min_height) * h / (kHeights - 1);
      const Eigen::Vector3d origin(0.0, 0.0, z);
      if (insideSolid(o, origin))
      {
        record(0.0, 0.0, static_cast<int>(i));
        touched = true;
        break;
      }
      const Eigen::Vector3d origin_local = o.toLocal(origin);
      for (int a = -n_angles; a <= n_angles; ++a)
      {
        const double angle = a * step;
        const Eigen::Vector3d dir(std::cos(angle), std::sin(angle), 0.0);
        double t;
        int part;
        if (o.intersect(origin_local, dir, 0.0, s.robot_radius, t, part))
        {
          record(angle, t, static_cast<int>(i));
          touched = true;
        }
      }
    }
  }
  return bits;
}

}  // namespace sl_sim
