// Scene files: reading, validation, bounds and the double-precision ray intersection API.
#include "sl_sim/scene.h"

#include <cmath>
#include <set>

#include <yaml-cpp/yaml.h>

#include "geometry.h"
#include "sl_rig/checked_yaml.h"

namespace sl_sim
{

const char* objectTypeName(ObjectType type)
{
  switch (type)
  {
    case ObjectType::Plane:
      return "plane";
    case ObjectType::Box:
      return "box";
    case ObjectType::Cylinder:
      return "cylinder";
  }
  return "?";
}

bool SceneObject::infinite() const
{
  return type == ObjectType::Plane &&
         (!(size.x() > 0.0) || !(size.y() > 0.0) || std::isinf(size.x()) || std::isinf(size.y()));
}

std::string SceneObject::label() const
{
  std::string s = objectTypeName(type);
  if (!name.empty())
    s += " '" + name + "'";
  return s;
}

Eigen::AlignedBox3d SceneObject::worldBounds() const
{
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::Matrix3d R = pose.linear();
  const Eigen::Vector3d c = pose.translation();
  Eigen::Vector3d extent;
  if (infinite())
  {
    // Bounded only along an axis the plane is perpendicular to.
    const Eigen::Vector3d n = R.col(2);
    extent = Eigen::Vector3d::Constant(inf);
    for (int i = 0; i < 3; ++i)
      if (std::abs(std::abs(n[i]) - 1.0) < 1e-12)
        extent[i] = 0.0;
    Eigen::AlignedBox3d box;
    for (int i = 0; i < 3; ++i)
    {
      box.min()[i] = extent[i] == 0.0 ? c[i] : -inf;
      box.max()[i] = extent[i] == 0.0 ? c[i] : inf;
    }
    return box;
  }
  if (type == ObjectType::Cylinder)
  {
    const double r = size.x(), h = size.z() / 2;
    for (int i = 0; i < 3; ++i)
    {
      const double az = R(i, 2);
      extent[i] = std::abs(az) * h + r * std::sqrt(std::max(0.0, 1.0 - az * az));
    }
  }
  else
  {
    const Eigen::Vector3d half =
        type == ObjectType::Plane ? Eigen::Vector3d(size.x() / 2, size.y() / 2, 0.0) : Eigen::Vector3d(size / 2);
    extent = R.cwiseAbs() * half;
  }
  return Eigen::AlignedBox3d(c - extent, c + extent);
}

void validateObject(const SceneObject& o)
{
  auto require = [](bool ok, const std::string& msg)
  {
    if (!ok)
      throw std::invalid_argument(msg);
  };
  require(o.pose.matrix().allFinite(), "position/orientation: must be finite");
  const Eigen::Matrix3d R = o.pose.linear();
  require((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6 && R.determinant() > 0.0,
          "orientation: must be a rotation");
  switch (o.type)
  {
    case ObjectType::Plane:
      require(!std::isnan(o.size.x()) && !std::isnan(o.size.y()) && o.size.x() >= 0.0 && o.size.y() >= 0.0,
              "size: must have 2 positive numbers (or be left out for an infinite plane)");
      require((o.size.x() > 0.0) == (o.size.y() > 0.0),
              "size: must have 2 positive numbers (or be left out for an "
              "infinite plane)");
      break;
    case ObjectType::Box:
      require(o.size.allFinite() && (o.size.array() > 0.0).all(), "size: must have 3 positive numbers");
      break;
    case ObjectType::Cylinder:
      require(std::isfinite(o.size.x()) && o.size.x() > 0.0, "radius: must be a positive number");
      require(std::isfinite(o.size.z()) && o.size.z() > 0.0, "height: must be a positive number");
      break;
  }
  const Material& m = o.material;
  require(std::isfinite(m.albedo) && m.albedo >= 0.0 && m.albedo <= 1.0, "albedo: must be in 0..1");
  require(std::isfinite(m.specular) && m.specular >= 0.0 && m.specular <= 1.0, "specular: must be in 0..1");
  require(std::isfinite(m.shininess) && m.shininess >= 1.0 && m.shininess <= 10000.0, "shininess: must be in 1..10000");
  const Texture& t = m.texture;
  switch (t.type)
  {
    case TextureType::None:
      break;
    case TextureType::Checker:
    case TextureType::Noise:
      require(std::isfinite(t.scale) && t.scale > 0.0, "texture.scale: must be a positive length, m");
      require(std::isfinite(t.contrast) && t.contrast >= 0.0 && t.contrast <= 1.0, "texture.contrast: must be in 0..1");
      break;
    case TextureType::Checkerboard:
      require(o.type == ObjectType::Plane, "texture.type: checkerboard is only for planes");
      require(t.cols >= 2 && t.cols <= 1000, "texture.cols: must be 2..1000 squares");
      require(t.rows >= 2 && t.rows <= 1000, "texture.rows: must be 2..1000 squares");
      require(std::isfinite(t.square) && t.square > 0.0, "texture.square: must be a positive length, m");
      require(std::isfinite(t.dark_albedo) && t.dark_albedo >= 0.0 && t.dark_albedo <= 1.0,
              "texture.dark_albedo: must be in 0..1");
      require(o.infinite() || (t.cols * t.square <= o.size.x() + 1e-9 && t.rows * t.square <= o.size.y() + 1e-9),
              "texture: the board (cols * square by rows * square) does not fit on the plane's size");
      break;
  }
}

namespace
{
// Parsing helpers: each throws std::invalid_argument starting with the key; the caller prefixes the
// file and the entry.
std::vector<double> numberList(const YAML::Node& node, const std::string& key, size_t n_min, size_t n_max)
{
  const std::string expected = n_min == n_max ? std::to_string(n_min) + " numbers"
                                              : std::to_string(n_min) + " to " + std::to_string(n_max) + " numbers";
  if (!node.IsSequence())
    throw std::invalid_argument(key + ": must be a list of " + expected);
  if (node.size() < n_min || node.size() > n_max)
    throw std::invalid_argument(key + ": has " + std::to_string(node.size()) + " numbers, expected " + expected);
  std::vector<double> v;
  for (const YAML::Node& e : node)
  {
    double x;
    try
    {
      x = e.as<double>();
    }
    catch (const YAML::Exception&)
    {
      throw std::invalid_argument(key + ": cannot read '" + (e.IsScalar() ? e.Scalar() : std::string("?")) +
                                  "' as a number");
    }
    if (!std::isfinite(x))
      throw std::invalid_argument(key + ": must be finite numbers");
    v.push_back(x);
  }
  return v;
}

template <typename T>
T scalarValue(const YAML::Node& node, const std::string& key)
{
  if (!node.IsScalar())
    throw std::invalid_argument(key + ": must be a single value");
  try
  {
    return node.as<T>();
  }
  catch (const YAML::Exception&)
  {
    const char* what = std::is_same<T, bool>::value ? "a boolean (true/false)"
                                                    : (std::is_same<T, int>::value ? "an integer" : "a number");
    throw std::invalid_argument(key + ": cannot read '" + node.Scalar() + "' as " + what);
  }
}

Eigen::Matrix3d rotationFromRpy(const std::vector<double>& rpy)
{
  return (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// Local frame of a plane given by its normal: x = up x n (to the right seen from the front), y = n x x.
Eigen::Matrix3d frameFromNormal(const Eigen::Vector3d& normal)
{
  const Eigen::Vector3d n = normal.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(n);
  if (x.norm() < 1e-9)
    x = Eigen::Vector3d::UnitX();  // horizontal plane: local x along world x
  x.normalize();
  const Eigen::Vector3d y = n.cross(x);
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = n;
  return R;
}

Texture parseTexture(const YAML::Node& node)
{
  Texture t;
  auto typeFrom = [](const std::string& s)
  {
    if (s == "none")
      return TextureType::None;
    if (s == "checker")
      return TextureType::Checker;
    if (s == "noise")
      return TextureType::Noise;
    if (s == "checkerboard")
      return TextureType::Checkerboard;
    throw std::invalid_argument("texture.type: unknown texture '" + s + "' (none, checker, noise, checkerboard)");
  };
  if (node.IsScalar())
  {
    t.type = typeFrom(node.Scalar());
    return t;
  }
  if (!node.IsMap())
    throw std::invalid_argument("texture: must be a texture name or a mapping with 'type'");
  sl_rig::checkKeys(node, { "type", "scale", "contrast", "cols", "rows", "square", "dark_albedo" }, "texture.");
  if (!node["type"])
    throw std::invalid_argument("texture.type: missing");
  t.type = typeFrom(scalarValue<std::string>(node["type"], "texture.type"));
  if (node["scale"])
    t.scale = scalarValue<double>(node["scale"], "texture.scale");
  if (node["contrast"])
    t.contrast = scalarValue<double>(node["contrast"], "texture.contrast");
  if (node["cols"])
    t.cols = scalarValue<int>(node["cols"], "texture.cols");
  if (node["rows"])
    t.rows = scalarValue<int>(node["rows"], "texture.rows");
  if (node["square"])
    t.square = scalarValue<double>(node["square"], "texture.square");
  if (node["dark_albedo"])
    t.dark_albedo = scalarValue<double>(node["dark_albedo"], "texture.dark_albedo");
  return t;
}

SceneObject parseObject(const YAML::Node& node)
{
  SceneObject o;
  if (!node.IsMap())
    throw std::invalid_argument("must be a mapping with 'type'");
  if (!node["type"])
    throw std::invalid_argument("type: missing (plane, box or cylinder)");
  const std::string type = scalarValue<std::string>(node["type"], "type");
  if (type == "plane")
    o.type = ObjectType::Plane;
  else if (type == "box")
    o.type = ObjectType::Box;
  else if (type == "cylinder")
    o.type = ObjectType::Cylinder;
  else
    throw std::invalid_argument("type: unknown type '" + type + "' (plane, box or cylinder)");
  return o;
}

void parseObjectBody(const YAML::Node& node, SceneObject& o)
{
  std::set<std::string> allowed = { "type",    "name",     "position",  "rpy",  "albedo",
                                    "texture", "specular", "shininess", "floor" };
  if (o.type == ObjectType::Plane)
    allowed.insert({ "normal", "size" });
  else if (o.type == ObjectType::Box)
    allowed.insert("size");
  else
    allowed.insert({ "radius", "height" });
  sl_rig::checkKeys(node, allowed, "");

  if (!node["position"])
    throw std::invalid_argument("position: missing (centre of the object, [x, y, z] m)");
  const std::vector<double> p = numberList(node["position"], "position", 3, 3);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (node["rpy"] && node["normal"])
    throw std::invalid_argument("normal: give either rpy or normal, not both");
  if (node["rpy"])
    R = rotationFromRpy(numberList(node["rpy"], "rpy", 3, 3));
  if (node["normal"])
  {
    const std::vector<double> n = numberList(node["normal"], "normal", 3, 3);
    const Eigen::Vector3d nv(n[0], n[1], n[2]);
    if (nv.norm() < 1e-9)
      throw std::invalid_argument("normal: must not be zero");
    R = frameFromNormal(nv);
  }
  o.pose.linear() = R;
  o.pose.translation() = Eigen::Vector3d(p[0], p[1], p[2]);

  switch (o.type)
  {
    case ObjectType::Plane:
      if (node["size"])
      {
        const std::vector<double> s = numberList(node["size"], "size", 2, 2);
        if (!(s[0] > 0.0 && s[1] > 0.0))
          throw std::invalid_argument("size: must have 2 positive numbers (or be left out for an infinite plane)");
        o.size = Eigen::Vector3d(s[0], s[1], 0.0);
      }
      break;
    case ObjectType::Box:
    {
      if (!node["size"])
        throw std::invalid_argument("size: missing (3 edge lengths, m)");
      std::vector<double> s;
      try
      {
        s = numberList(node["size"], "size", 3, 3);
      }
      catch (const std::invalid_argument&)
      {
        throw std::invalid_argument("size: must have 3 positive numbers");
      }
      o.size = Eigen::Vector3d(s[0], s[1], s[2]);
      break;
    }
    case ObjectType::Cylinder:
      if (!node["radius"])
        throw std::invalid_argument("radius: missing (m)");
      if (!node["height"])
        throw std::invalid_argument("height: missing (m)");
      o.size.x() = o.size.y() = scalarValue<double>(node["radius"], "radius");
      o.size.z() = scalarValue<double>(node["height"], "height");
      break;
  }
  if (node["albedo"])
    o.material.albedo = scalarValue<double>(node["albedo"], "albedo");
  if (node["specular"])
    o.material.specular = scalarValue<double>(node["specular"], "specular");
  if (node["shininess"])
    o.material.shininess = scalarValue<double>(node["shininess"], "shininess");
  if (node["texture"])
    o.material.texture = parseTexture(node["texture"]);
  if (node["floor"])
    o.floor = scalarValue<bool>(node["floor"], "floor");
  validateObject(o);
}

// Everything below the top-level mapping; throws SceneFileError naming the file and the key.
Scene parseRoot(const YAML::Node& root, const std::string& source)
{
  try
  {
    sl_rig::checkKeys(root, { "format_version", "name", "description", "objects" }, "");
  }
  catch (const std::invalid_argument& e)
  {
    throw SceneFileError(source + ": " + e.what());
  }
  Scene scene;
  if (root["format_version"])
  {
    int version = 0;
    try
    {
      version = scalarValue<int>(root["format_version"], "format_version");
    }
    catch (const std::invalid_argument& e)
    {
      throw SceneFileError(source + ": " + e.what());
    }
    if (version != 1)
      throw SceneFileError(source + ": format_version: is " + std::to_string(version) +
                           ", this software reads version 1");
  }
  if (root["name"] && root["name"].IsScalar())
    scene.name = root["name"].Scalar();
  const YAML::Node objects = root["objects"];
  if (!objects)
    throw SceneFileError(source + ": objects: missing (a list of planes, boxes and cylinders)");
  if (!objects.IsSequence() || objects.size() == 0)
    throw SceneFileError(source + ": objects: must be a non-empty list");
  for (size_t i = 0; i < objects.size(); ++i)
  {
    const YAML::Node node = objects[i];
    std::string entry = "objects[" + std::to_string(i) + "]";
    try
    {
      SceneObject o = parseObject(node);
      if (node["name"])
      {
        const YAML::Node n = node["name"];
        if (!n.IsScalar())
          throw std::invalid_argument("name: must be a string");
        o.name = n.Scalar();
      }
      entry += " (" + o.label() + ")";
      parseObjectBody(node, o);
      scene.objects.push_back(o);
    }
    catch (const std::invalid_argument& e)
    {
      throw SceneFileError(source + ": " + entry + ": " + e.what());
    }
    catch (const YAML::Exception& e)
    {
      throw SceneFileError(source + ": " + entry + ": " + e.what());
    }
  }
  return scene;
}
}  // namespace

Scene parseScene(const std::string& text, const std::string& source)
{
  return sl_rig::parseMappingFile<SceneFileError>(text, source, " with 'objects'",
                                                  [&](const YAML::Node& root) { return parseRoot(root, source); });
}

Scene loadScene(const std::string& path)
{
  return parseScene(sl_rig::readFileText<SceneFileError>(path, "scene file"), path);
}

std::vector<Eigen::Vector3d> checkerboardInnerCorners(const SceneObject& o)
{
  if (o.type != ObjectType::Plane || o.material.texture.type != TextureType::Checkerboard)
    throw std::invalid_argument("checkerboardInnerCorners: " + o.label() +
                                " is not a plane with a checkerboard texture");
  const Texture& t = o.material.texture;
  std::vector<Eigen::Vector3d> corners;
  for (int j = 1; j < t.rows; ++j)
    for (int i = 1; i < t.cols; ++i)
      corners.push_back(
          o.pose * Eigen::Vector3d(-t.cols * t.square / 2 + i * t.square, -t.rows * t.square / 2 + j * t.square, 0.0));
  return corners;
}

bool intersectObject(const SceneObject& object, const Ray& ray, double t_min, double t_max, Hit& hit)
{
  sim::PreparedObject<double> p;
  p.set(object, object.pose, hit.object);
  double t;
  int part;
  if (!p.intersect(p.toLocal(ray.origin), ray.direction, t_min, t_max, t, part))
    return false;
  hit.t = t;
  hit.part = part;
  hit.point = ray.origin + t * ray.direction;
  const Eigen::Vector3d pl = p.toLocal(hit.point);
  hit.normal = p.normal(pl, part);
  if (object.type == ObjectType::Plane && hit.normal.dot(ray.direction) > 0.0)
    hit.normal = -hit.normal;
  hit.uv = p.uv(pl, part);
  return true;
}

bool intersectScene(const Scene& scene, const Ray& ray, Hit& hit, double t_min, double t_max)
{
  bool found = false;
  for (size_t i = 0; i < scene.objects.size(); ++i)
  {
    Hit h;
    h.object = static_cast<int>(i);
    if (intersectObject(scene.objects[i], ray, t_min, t_max, h))
    {
      hit = h;
      t_max = h.t;
      found = true;
    }
  }
  return found;
}

}  // namespace sl_sim
