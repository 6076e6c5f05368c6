// Rig (calibration) file reading, writing and validation.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "sl_rig/checked_yaml.h"
#include "sl_rig/rig.h"

namespace sl_projector
{

namespace
{
[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what)
{
  throw RigFileError(source + ": " + key + ": " + what);
}

// Subscripting a scalar or a list throws YAML::BadSubscript, which names neither file nor key:
// every lookup goes through a mapping checked here first.
void requireMap(const YAML::Node& node, const std::string& path, const std::string& source)
{
  if (!node.IsMap())
    fail(source, path.empty() ? std::string("<top level>") : path, "must be a mapping");
}

// Refuses a key of mapping @p node outside @p allowed (a misspelt optional key must not leave its
// default in place unnoticed).
void checkKeys(const YAML::Node& node, const std::set<std::string>& allowed, const std::string& path,
               const std::string& source)
{
  requireMap(node, path, source);
  try
  {
    sl_rig::checkKeys(node, allowed, path.empty() ? std::string() : path + ".");
  }
  catch (const std::invalid_argument& e)
  {
    throw RigFileError(source + ": " + e.what());
  }
}

YAML::Node child(const YAML::Node& node, const std::string& name, const std::string& path, const std::string& source)
{
  requireMap(node, path, source);
  const YAML::Node c = node[name];
  if (!c)
    fail(source, path.empty() ? name : path + "." + name, "missing");
  return c;
}

template <typename T>
T scalar(const YAML::Node& node, const std::string& name, const std::string& path, const std::string& source)
{
  const std::string key = path.empty() ? name : path + "." + name;
  const YAML::Node c = child(node, name, path, source);
  if (!c.IsScalar())
    fail(source, key, "must be a single value");
  try
  {
    return c.as<T>();
  }
  catch (const YAML::Exception&)
  {
    fail(source, key, "cannot read '" + c.Scalar() + "' as a " + (std::is_same<T, bool>::value ? "boolean" : "number"));
  }
}

// The child @p name of mapping @p node, or an undefined node if it is absent.
YAML::Node optionalChild(const YAML::Node& node, const std::string& name, const std::string& path,
                         const std::string& source)
{
  requireMap(node, path, source);
  return node[name];
}

template <typename T>
T scalarOr(const YAML::Node& node, const std::string& name, const std::string& path, const std::string& source,
           const T& fallback)
{
  return optionalChild(node, name, path, source) ? scalar<T>(node, name, path, source) : fallback;
}

std::vector<double> numbers(const YAML::Node& node, const std::string& name, const std::string& path,
                            const std::string& source, size_t min_size, size_t max_size)
{
  const std::string key = path.empty() ? name : path + "." + name;
  const YAML::Node c = child(node, name, path, source);
  if (!c.IsSequence())
    fail(source, key, "must be a list of numbers");
  if (c.size() < min_size || c.size() > max_size)
  {
    std::ostringstream what;
    what << "has " << c.size() << " numbers, expected " << min_size;
    if (max_size != min_size)
      what << " to " << max_size;
    fail(source, key, what.str());
  }
  std::vector<double> out;
  out.reserve(c.size());
  for (size_t i = 0; i < c.size(); ++i)
  {
    try
    {
      out.push_back(c[i].as<double>());
    }
    catch (const YAML::Exception&)
    {
      fail(source, key + "[" + std::to_string(i) + "]", "is not a number");
    }
  }
  return out;
}

PinholeModel readPinhole(const YAML::Node& root, const std::string& name, const std::string& source, LensOptics& optics)
{
  const YAML::Node n = child(root, name, "", source);
  checkKeys(n, { "width", "height", "K", "D", "focus_distance", "f_number", "pixel_pitch" }, name, source);
  // The optics are optional: a rig file without them has the defaults of its device.
  optics.focus_distance = scalarOr<double>(n, "focus_distance", name, source, optics.focus_distance);
  optics.f_number = scalarOr<double>(n, "f_number", name, source, optics.f_number);
  optics.pixel_pitch = scalarOr<double>(n, "pixel_pitch", name, source, optics.pixel_pitch);
  PinholeModel m;
  m.width = scalar<int>(n, "width", name, source);
  m.height = scalar<int>(n, "height", name, source);
  const std::vector<double> K = numbers(n, "K", name, source, 9, 9);
  if (K[1] != 0.0 || K[3] != 0.0 || K[6] != 0.0 || K[7] != 0.0 || K[8] != 1.0)
    fail(source, name + ".K", "must be [fx, 0, cx, 0, fy, cy, 0, 0, 1] (no skew)");
  m.fx = K[0];
  m.cx = K[2];
  m.fy = K[4];
  m.cy = K[5];
  // plumb_bob: k1, k2, p1, p2[, k3]
  const std::vector<double> D = numbers(n, "D", name, source, 4, 5);
  for (size_t i = 0; i < D.size(); ++i)
    m.dist[i] = D[i];
  return m;
}

Eigen::Vector3d vec3(const YAML::Node& node, const std::string& name, const std::string& path,
                     const std::string& source)
{
  const std::vector<double> v = numbers(node, name, path, source, 3, 3);
  return { v[0], v[1], v[2] };
}

std::vector<DepthModel> readModels(const YAML::Node& tables, const std::string& name, bool rational, size_t count,
                                   const std::string& source)
{
  std::vector<DepthModel> out;
  const YAML::Node t = optionalChild(tables, name, "depth_tables", source);
  if (!t)
    return out;
  const std::string path = "depth_tables." + name;
  checkKeys(t, rational ? std::set<std::string>{ "a", "b", "c", "rms" } : std::set<std::string>{ "a", "b", "rms" },
            path, source);
  const std::vector<double> a = numbers(t, "a", path, source, count, count);
  const std::vector<double> b = numbers(t, "b", path, source, count, count);
  const std::vector<double> c =
      rational ? numbers(t, "c", path, source, count, count) : std::vector<double>(count, 0.0);
  const std::vector<double> rms = numbers(t, "rms", path, source, count, count);
  out.resize(count);
  for (size_t i = 0; i < count; ++i)
  {
    DepthModel& m = out[i];
    m.valid = std::isfinite(a[i]) && std::isfinite(b[i]) && std::isfinite(c[i]);
    if (m.valid)
    {
      m.a = a[i];
      m.b = b[i];
      m.c = c[i];
      m.rms = rms[i];
    }
  }
  return out;
}

void requireThat(bool ok, const std::string& key, const std::string& what)
{
  if (!ok)
    throw std::invalid_argument(key + ": " + what);
}

// A frame id as ROS names are written: letters, digits, '_' and '/'.
bool isFrameName(const std::string& name)
{
  if (name.empty())
    return false;
  for (const char c : name)
  {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '/';
    if (!ok)
      return false;
  }
  return true;
}

// @p text for a message: non-printable bytes as '?', at most 64 of them.
std::string printable(const std::string& text)
{
  std::string out = text.substr(0, 64);
  for (char& c : out)
    if (c < 0x20 || c > 0x7e)
      c = '?';
  return out;
}

void validatePinhole(const PinholeModel& m, const std::string& name)
{
  requireThat(m.width > 0, name + ".width", "must be > 0");
  requireThat(m.height > 0, name + ".height", "must be > 0");
  // Bounded before anything sizes a buffer by width * height (which overflowed int and crashed the
  // decoder at 262144 x 262144).
  const std::string side_limit = "must be at most " + std::to_string(kMaxImageSide) + " px";
  requireThat(m.width <= kMaxImageSide, name + ".width", side_limit + ", got " + std::to_string(m.width));
  requireThat(m.height <= kMaxImageSide, name + ".height", side_limit + ", got " + std::to_string(m.height));
  const int64_t pixels = static_cast<int64_t>(m.width) * m.height;
  requireThat(pixels <= kMaxImagePixels, name + ".width, " + name + ".height",
              std::to_string(m.width) + " x " + std::to_string(m.height) + " = " + std::to_string(pixels) +
                  " px, more than the " + std::to_string(kMaxImagePixels) + " px allowed");
  requireThat(std::isfinite(m.fx) && m.fx > 0.0 && std::isfinite(m.fy) && m.fy > 0.0, name + ".K",
              "focal lengths must be finite and > 0");
  requireThat(std::isfinite(m.cx) && std::isfinite(m.cy), name + ".K", "principal point must be finite");
  for (double d : m.dist)
    requireThat(std::isfinite(d), name + ".D", "must be finite");
}

void validateOptics(const LensOptics& o, const PinholeModel& m, const std::string& name)
{
  requireThat(std::isfinite(o.pixel_pitch) && o.pixel_pitch > 0.0 && o.pixel_pitch < 1e-3, name + ".pixel_pitch",
              "must be a pitch in metres, > 0 and < 1 mm");
  requireThat(std::isfinite(o.f_number) && o.f_number >= 0.5 && o.f_number <= 64.0, name + ".f_number",
              "must be in 0.5..64");
  const double focal = std::max(m.fx, m.fy) * o.pixel_pitch;
  requireThat(std::isfinite(o.focus_distance) && o.focus_distance > 1.5 * focal && o.focus_distance <= 1000.0,
              name + ".focus_distance",
              "must be in metres, beyond 1.5 focal lengths (fx * pixel_pitch = " + std::to_string(focal) +
                  " m) and at most 1000 m");
}
}  // namespace

void Rig::validate() const
{
  validatePinhole(camera, "camera");
  validatePinhole(projector, "projector");
  validateOptics(camera_optics, camera, "camera");
  validateOptics(projector_optics, projector, "projector");
  const Eigen::Matrix3d& R = projector_pose.rotation;
  requireThat(R.allFinite(), "projector_pose.rotation", "must be finite");
  const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  requireThat(orthogonality < 1e-5, "projector_pose.rotation",
              "is not orthonormal (max |R^T R - I| = " + std::to_string(orthogonality) + ")");
  requireThat(R.determinant() > 0.0, "projector_pose.rotation", "is a reflection (determinant < 0)");
  requireThat(projector_pose.translation.allFinite(), "projector_pose.translation", "must be finite");
  requireThat(projector_pose.translation.norm() > 1e-4, "projector_pose.translation",
              "the baseline must be longer than 0.1 mm");
  requireThat(projector_pose.translation.norm() < 10.0, "projector_pose.translation",
              "a baseline over 10 m is not metres (mm given?)");
  requireThat(pattern.projector_width == projector.width && pattern.projector_height == projector.height, "pattern",
              "frame size differs from projector.width/height");
  try
  {
    pattern.validate();
    Pattern check(pattern);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("pattern.") + e.what());
  }
  requireThat(mount.xyz.allFinite() && mount.rpy.allFinite(), "mount", "must be finite");
  // The URDF and tf take it as it is. Control bytes or invalid UTF-8 did not even survive
  // rigToYaml() (found by fuzz/rig_parser_fuzz.cpp).
  requireThat(isFrameName(mount.parent_frame), "mount.parent_frame",
              "must be a frame name (letters, digits, '_' and '/'), got '" + printable(mount.parent_frame) + "'");
  const size_t cells = static_cast<size_t>(pattern.rows) * static_cast<size_t>(pattern.cols);
  requireThat(tables.linear.empty() || tables.linear.size() == cells, "depth_tables.linear",
              "must have rows * cols entries");
  requireThat(tables.rational.empty() || tables.rational.size() == cells, "depth_tables.rational",
              "must have rows * cols entries");
}

namespace
{
Rig parseRoot(const YAML::Node& root, const std::string& source)
{
  checkKeys(root, { "format_version", "camera", "projector", "projector_pose", "pattern", "mount", "depth_tables" }, "",
            source);
  const int version = scalar<int>(root, "format_version", "", source);
  if (version != 1)
    fail(source, "format_version", "is " + std::to_string(version) + ", this software reads version 1");

  Rig rig;
  rig.camera = readPinhole(root, "camera", source, rig.camera_optics);
  rig.projector = readPinhole(root, "projector", source, rig.projector_optics);

  const YAML::Node pose = child(root, "projector_pose", "", source);
  checkKeys(pose, { "rotation", "translation" }, "projector_pose", source);
  const std::vector<double> R = numbers(pose, "rotation", "projector_pose", source, 9, 9);
  rig.projector_pose.rotation << R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8];
  rig.projector_pose.translation = vec3(pose, "translation", "projector_pose", source);

  const YAML::Node p = child(root, "pattern", "", source);
  checkKeys(p,
            { "rows", "cols", "primitive_width", "primitive_height", "gap_x", "gap_y", "offset_x", "offset_y", "flip_x",
              "flip_y" },
            "pattern", source);
  PatternConfig& pc = rig.pattern;
  pc.rows = scalar<int>(p, "rows", "pattern", source);
  pc.cols = scalar<int>(p, "cols", "pattern", source);
  pc.primitive_width = scalarOr<int>(p, "primitive_width", "pattern", source, pc.primitive_width);
  pc.primitive_height = scalarOr<int>(p, "primitive_height", "pattern", source, pc.primitive_height);
  pc.gap_x = scalarOr<int>(p, "gap_x", "pattern", source, pc.gap_x);
  pc.gap_y = scalarOr<int>(p, "gap_y", "pattern", source, pc.gap_y);
  pc.offset_x = scalarOr<int>(p, "offset_x", "pattern", source, pc.offset_x);
  pc.offset_y = scalarOr<int>(p, "offset_y", "pattern", source, pc.offset_y);
  pc.flip_x = scalarOr<bool>(p, "flip_x", "pattern", source, pc.flip_x);
  pc.flip_y = scalarOr<bool>(p, "flip_y", "pattern", source, pc.flip_y);
  pc.projector_width = rig.projector.width;
  pc.projector_height = rig.projector.height;

  if (const YAML::Node m = optionalChild(root, "mount", "", source))
  {
    checkKeys(m, { "parent_frame", "xyz", "rpy" }, "mount", source);
    rig.mount.parent_frame = scalarOr<std::string>(m, "parent_frame", "mount", source, rig.mount.parent_frame);
    rig.mount.xyz = vec3(m, "xyz", "mount", source);
    rig.mount.rpy = vec3(m, "rpy", "mount", source);
  }

  if (const YAML::Node t = optionalChild(root, "depth_tables", "", source))
  {
    checkKeys(t, { "distances", "linear", "rational" }, "depth_tables", source);
    const size_t cells = static_cast<size_t>(std::max(0, pc.rows)) * static_cast<size_t>(std::max(0, pc.cols));
    if (optionalChild(t, "distances", "depth_tables", source))
      rig.tables.distances = numbers(t, "distances", "depth_tables", source, 0, 1000);
    rig.tables.linear = readModels(t, "linear", false, cells, source);
    rig.tables.rational = readModels(t, "rational", true, cells, source);
  }

  try
  {
    rig.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw RigFileError(source + ": " + e.what());
  }
  return rig;
}
}  // namespace

Rig parseRig(const std::string& text, const std::string& source)
{
  return sl_rig::parseMappingFile<RigFileError>(text, source, "",
                                                [&](const YAML::Node& root) { return parseRoot(root, source); });
}

Rig loadRig(const std::string& path)
{
  return parseRig(sl_rig::readFileText<RigFileError>(path, "calibration file"), path);
}

namespace
{
// The shortest text that reads back as the same double, so that a rig written and read again is
// the same rig. Rounded to 12 digits, a baseline of 0.1000000000001 mm became the 0.1 mm limit and
// parseRig() refused what rigToYaml() wrote (found by fuzz/rig_parser_fuzz.cpp).
std::string exactText(double x)
{
  if (std::isnan(x))
    return ".nan";  // YAML's NaN literal: an entry without a value
  if (std::isinf(x))
    return x > 0.0 ? ".inf" : "-.inf";
  char text[32];
  const std::to_chars_result r = std::to_chars(text, text + sizeof(text), x);
  std::string s(text, r.ptr);
  // "5e-04" is a string to YAML 1.1 readers (PyYAML): a float needs its '.'.
  const size_t e = s.find('e');
  if (e != std::string::npos && s.find('.') == std::string::npos)
    s.insert(e, ".0");
  return s;
}

void emitNumbers(YAML::Emitter& out, const std::vector<double>& v)
{
  out << YAML::Flow << YAML::BeginSeq;
  for (double x : v)
    out << exactText(x);
  out << YAML::EndSeq;
}

void emitPinhole(YAML::Emitter& out, const std::string& name, const PinholeModel& m, const LensOptics& o)
{
  out << YAML::Key << name << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "width" << YAML::Value << m.width;
  out << YAML::Key << "height" << YAML::Value << m.height;
  out << YAML::Key << "K" << YAML::Value;
  emitNumbers(out, { m.fx, 0.0, m.cx, 0.0, m.fy, m.cy, 0.0, 0.0, 1.0 });
  out << YAML::Key << "D" << YAML::Value;
  emitNumbers(out, std::vector<double>(m.dist.begin(), m.dist.end()));
  out << YAML::Key << "focus_distance" << YAML::Value << exactText(o.focus_distance);
  out << YAML::Key << "f_number" << YAML::Value << exactText(o.f_number);
  out << YAML::Key << "pixel_pitch" << YAML::Value << exactText(o.pixel_pitch);
  out << YAML::EndMap;
}

void emitModels(YAML::Emitter& out, const std::string& name, const std::vector<DepthModel>& models, bool rational)
{
  if (models.empty())
    return;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> a, b, c, rms;
  for (const DepthModel& m : models)
  {
    a.push_back(m.valid ? m.a : nan);
    b.push_back(m.valid ? m.b : nan);
    c.push_back(m.valid ? m.c : nan);
    rms.push_back(m.valid ? m.rms : nan);
  }
  out << YAML::Key << name << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "a" << YAML::Value;
  emitNumbers(out, a);
  out << YAML::Key << "b" << YAML::Value;
  emitNumbers(out, b);
  if (rational)
  {
    out << YAML::Key << "c" << YAML::Value;
    emitNumbers(out, c);
  }
  out << YAML::Key << "rms" << YAML::Value;
  emitNumbers(out, rms);
  out << YAML::EndMap;
}
}  // namespace

std::string rigToYaml(const Rig& rig)
{
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "format_version" << YAML::Value << 1;
  emitPinhole(out, "camera", rig.camera, rig.camera_optics);
  emitPinhole(out, "projector", rig.projector, rig.projector_optics);
  out << YAML::Key << "projector_pose" << YAML::Value << YAML::BeginMap;
  const Eigen::Matrix3d& R = rig.projector_pose.rotation;
  out << YAML::Key << "rotation" << YAML::Value;
  emitNumbers(out, { R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2) });
  out << YAML::Key << "translation" << YAML::Value;
  const Eigen::Vector3d& t = rig.projector_pose.translation;
  emitNumbers(out, { t.x(), t.y(), t.z() });
  out << YAML::EndMap;
  const PatternConfig& p = rig.pattern;
  out << YAML::Key << "pattern" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rows" << YAML::Value << p.rows << YAML::Key << "cols" << YAML::Value << p.cols;
  out << YAML::Key << "primitive_width" << YAML::Value << p.primitive_width;
  out << YAML::Key << "primitive_height" << YAML::Value << p.primitive_height;
  out << YAML::Key << "gap_x" << YAML::Value << p.gap_x << YAML::Key << "gap_y" << YAML::Value << p.gap_y;
  out << YAML::Key << "offset_x" << YAML::Value << p.offset_x << YAML::Key << "offset_y" << YAML::Value << p.offset_y;
  out << YAML::Key << "flip_x" << YAML::Value << p.flip_x << YAML::Key << "flip_y" << YAML::Value << p.flip_y;
  out << YAML::EndMap;
  out << YAML::Key << "mount" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "parent_frame" << YAML::Value << rig.mount.parent_frame;
  out << YAML::Key << "xyz" << YAML::Value;
  emitNumbers(out, { rig.mount.xyz.x(), rig.mount.xyz.y(), rig.mount.xyz.z() });
  out << YAML::Key << "rpy" << YAML::Value;
  emitNumbers(out, { rig.mount.rpy.x(), rig.mount.rpy.y(), rig.mount.rpy.z() });
  out << YAML::EndMap;
  if (!rig.tables.linear.empty() || !rig.tables.rational.empty())
  {
    out << YAML::Key << "depth_tables" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "distances" << YAML::Value;
    emitNumbers(out, rig.tables.distances);
    emitModels(out, "linear", rig.tables.linear, false);
    emitModels(out, "rational", rig.tables.rational, true);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string("# structured-light rig calibration (rig file: sl_rig/README.md)\n") + out.c_str() + "\n";
}

void saveRig(const Rig& rig, const std::string& path)
{
  std::ofstream out(path);
  if (!out)
    throw RigFileError(path + ": cannot write the calibration file");
  out << rigToYaml(rig);
  if (!out)
    throw RigFileError(path + ": write failed");
}

}  // namespace sl_projector
