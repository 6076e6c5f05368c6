// Fuzz target: sl_rig's parseRig on arbitrary text (the rig / calibration file).
//
// The documented error path is RigFileError; any other exception escapes and counts as a finding.
// An accepted rig must also pass Rig::validate() and round-trip exactly through rigToYaml() (rig.h).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "fuzz_input.h"
#include "sl_rig/rig.h"

namespace
{
using sl_projector::Rig;

// rigToYaml() writes every number so that it reads back exactly.
bool same(double a, double b)
{
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

bool samePinhole(const sl_projector::PinholeModel& a, const sl_projector::PinholeModel& b)
{
  bool equal = a.width == b.width && a.height == b.height && same(a.fx, b.fx) && same(a.fy, b.fy) && same(a.cx, b.cx) &&
               same(a.cy, b.cy);
  for (size_t i = 0; i < a.dist.size(); ++i)
    equal = equal && same(a.dist[i], b.dist[i]);
  return equal;
}

bool sameModels(const std::vector<sl_projector::DepthModel>& a, const std::vector<sl_projector::DepthModel>& b)
{
  bool equal = a.size() == b.size();
  for (size_t i = 0; equal && i < a.size(); ++i)
    equal = a[i].valid == b[i].valid && (!a[i].valid || (same(a[i].a, b[i].a) && same(a[i].b, b[i].b) &&
                                                         same(a[i].c, b[i].c) && same(a[i].rms, b[i].rms)));
  return equal;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  Rig rig;
  try
  {
    rig = sl_projector::parseRig(text, "fuzz.yaml");
  }
  catch (const sl_projector::RigFileError&)
  {
    return 0;  // refused, naming the file: the documented error path
  }
  rig.validate();  // an accepted rig is valid (std::invalid_argument here is a finding)

  const std::string yaml = sl_projector::rigToYaml(rig);
  Rig back;
  try
  {
    back = sl_projector::parseRig(yaml, "round trip");
  }
  catch (const sl_projector::RigFileError& e)
  {
    std::fprintf(stderr, "rigToYaml() output refused: %s\n%s\n", e.what(), yaml.c_str());
    FUZZ_CHECK(!"rigToYaml() round-trips through parseRig()");
  }
  FUZZ_CHECK(samePinhole(back.camera, rig.camera));
  FUZZ_CHECK(samePinhole(back.projector, rig.projector));
  for (int i = 0; i < 9; ++i)
    FUZZ_CHECK(same(back.projector_pose.rotation(i / 3, i % 3), rig.projector_pose.rotation(i / 3, i % 3)));
  for (int i = 0; i < 3; ++i)
  {
    FUZZ_CHECK(same(back.projector_pose.translation[i], rig.projector_pose.translation[i]));
    FUZZ_CHECK(same(back.mount.xyz[i], rig.mount.xyz[i]));
    FUZZ_CHECK(same(back.mount.rpy[i], rig.mount.rpy[i]));
  }
  const sl_projector::PatternConfig &p = rig.pattern, &q = back.pattern;
  FUZZ_CHECK(p.rows == q.rows && p.cols == q.cols && p.primitive_width == q.primitive_width &&
             p.primitive_height == q.primitive_height && p.gap_x == q.gap_x && p.gap_y == q.gap_y &&
             p.offset_x == q.offset_x && p.offset_y == q.offset_y && p.flip_x == q.flip_x && p.flip_y == q.flip_y);
  FUZZ_CHECK(back.mount.parent_frame == rig.mount.parent_frame);
  FUZZ_CHECK(sameModels(back.tables.linear, rig.tables.linear));
  FUZZ_CHECK(sameModels(back.tables.rational, rig.tables.rational));
  return 0;
}
