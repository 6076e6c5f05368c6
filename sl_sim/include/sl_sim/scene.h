#pragma once
/// @file scene.h
/// @brief Scenes for the projector-camera simulator: planes, boxes and cylinders with materials,
/// read from YAML, and exact ray-scene intersection (ROS-free).
///
/// World frame: z up, metres (REP 103). The scene file format is documented in the package README
/// (section "Simulator", "Scene files").

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sl_sim
{

/// @brief Kind of a scene object.
enum class ObjectType
{
  Plane,    ///< a plane, infinite or a rectangle (two-sided)
  Box,      ///< a closed box of any orientation
  Cylinder  ///< a closed cylinder (side and both caps) of any orientation
};

/// @brief Name of an object type as written in scene files ("plane", "box", "cylinder").
const char* objectTypeName(ObjectType type);

/// @brief Kind of a surface texture (an albedo modulation).
enum class TextureType
{
  None,         ///< uniform albedo
  Checker,      ///< an infinite checker of square `scale` m: every other square is darker by `contrast`
  Noise,        ///< smooth fractal value noise of feature size `scale` m, darkening by up to `contrast`
  Checkerboard  ///< a calibration board: `cols` x `rows` squares of `square` m on a margin of `albedo`
};

/**
 * @brief Albedo texture of a surface, in the surface's texture coordinates (metres).
 *
 * Texture coordinates (u, v): planes and box faces use the two in-surface local axes (for a box face
 * the two other local axes, in x, y, z order); cylinders use (radius * azimuth, local z).
 */
struct Texture
{
  TextureType type = TextureType::None;  ///< kind
  double scale = 0.02;                   ///< checker square or noise feature size, m
  double contrast = 0.5;                 ///< checker / noise: darkest albedo = albedo * (1 - contrast), 0..1
  // Checkerboard (calibration board) only:
  int cols = 8;               ///< squares along the local x axis
  int rows = 6;               ///< squares along the local y axis
  double square = 0.03;       ///< square size, m
  double dark_albedo = 0.05;  ///< albedo of the dark squares (the light ones have the object's albedo)
};

/// @brief Reflectance of a surface: Lambertian albedo with a texture, plus a Blinn-Phong lobe.
struct Material
{
  double albedo = 0.7;      ///< diffuse reflectance, 0..1
  Texture texture;          ///< albedo modulation
  double specular = 0.0;    ///< weight of the normalised Blinn-Phong lobe, 0..1 (0: matte)
  double shininess = 50.0;  ///< Blinn-Phong exponent (>= 1; larger: smaller, brighter highlight)
};

/**
 * @brief One object of a scene.
 *
 * Every object has a pose: `position` (its centre) and `orientation` (its local axes in the world).
 * Plane: local z is the normal; a bounded plane is the rectangle |x| <= size.x/2, |y| <= size.y/2.
 * Box: the local axis-aligned box of full edge lengths `size`. Cylinder: axis along local z,
 * `radius` = size.x, full `height` = size.z.
 */
struct SceneObject
{
  ObjectType type = ObjectType::Plane;                     ///< kind
  std::string name;                                        ///< name from the file (may be empty)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< object frame in the world
  /// Plane: (size x, size y, 0), 0 or infinity for an infinite plane. Box: full edge lengths.
  /// Cylinder: (radius, radius, height).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Material material;   ///< surface
  bool floor = false;  ///< marked as floor: never a contact for the robot's bumpers

  /// @brief True for an infinite plane.
  bool infinite() const;

  /**
   * @brief Axis-aligned bounding box in the world (min, max); infinite components for infinite
   * planes that are not axis-aligned.
   */
  Eigen::AlignedBox3d worldBounds() const;

  /// @brief "objects[i] (type 'name')" style label used in messages (without the index).
  std::string label() const;
};

/// @brief A scene: a list of objects, all in the world frame.
struct Scene
{
  std::string name;                  ///< optional name from the file
  std::vector<SceneObject> objects;  ///< objects in file order
};

/// @brief Thrown for an unreadable or invalid scene file; what() names the file and the entry,
/// for example `room.yaml: objects[3] (box 'table'): size: must have 3 positive numbers`.
class SceneFileError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/**
 * @brief Loads a scene file (YAML, format in the README).
 * @throws SceneFileError naming @p path and the offending entry.
 */
Scene loadScene(const std::string& path);

/**
 * @brief Parses a scene from YAML text; @p source names it in error messages.
 * @throws SceneFileError as loadScene().
 */
Scene parseScene(const std::string& yaml_text, const std::string& source = "<string>");

/**
 * @brief Checks one object (sizes, albedo, texture, finite pose).
 * @throws std::invalid_argument whose message starts with the offending key (e.g. "size: ...").
 */
void validateObject(const SceneObject& object);

/**
 * @brief Inner corners of a checkerboard-textured plane, in the world frame.
 *
 * The board of cols x rows squares is centred on the plane's position; square (0, 0) is the dark
 * square at the plane's most negative local x and y. Inner corner (i, j), i = 1..cols-1,
 * j = 1..rows-1, lies at local (-cols*square/2 + i*square, -rows*square/2 + j*square, 0); the
 * result is ordered with i fastest: index (j-1)*(cols-1) + (i-1).
 * @throws std::invalid_argument if @p object is not a plane with a checkerboard texture.
 */
std::vector<Eigen::Vector3d> checkerboardInnerCorners(const SceneObject& object);

/// @brief A ray: origin + t * direction (the direction need not be unit length; t is in its units).
struct Ray
{
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();      ///< start point
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  ///< direction (non-zero)
};

/// @brief The nearest intersection of a ray with a scene.
struct Hit
{
  double t = std::numeric_limits<double>::infinity();  ///< ray parameter of the hit
  Eigen::Vector3d point = Eigen::Vector3d::Zero();     ///< hit point, world
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();    ///< unit outward normal (planes: facing the ray)
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();        ///< texture coordinates, m
  int object = -1;                                     ///< index in Scene::objects, -1 for none
  int part = 0;  ///< box face 0..5 (+x, -x, +y, -y, +z, -z); cylinder 0 side, 1 top, 2 bottom
};

/**
 * @brief Intersects a ray with one object: the smallest t in (t_min, t_max).
 *
 * Boxes and cylinders are closed solids: a ray starting inside hits the surface on its way out.
 * @return true and fills @p hit (object index left unchanged) on a hit.
 */
bool intersectObject(const SceneObject& object, const Ray& ray, double t_min, double t_max, Hit& hit);

/**
 * @brief Nearest intersection of a ray with any object of @p scene within (t_min, t_max).
 * @return true on a hit; @p hit.object is the object's index.
 */
bool intersectScene(const Scene& scene, const Ray& ray, Hit& hit, double t_min = 1e-9,
                    double t_max = std::numeric_limits<double>::infinity());

}  // namespace sl_sim
