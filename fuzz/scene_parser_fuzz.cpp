// Fuzz target: sl_sim's parseScene on arbitrary text (the simulator's scene files).
//
// The documented error path is SceneFileError; any other exception escapes and counts as a
// finding. An accepted scene's objects must pass validateObject(), and the geometry the simulator
// uses next (bounds, ray intersection, checkerboard corners) must run on them without a fault.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.h"
#include "sl_sim/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  sl_sim::Scene scene;
  try
  {
    scene = sl_sim::parseScene(text, "fuzz.yaml");
  }
  catch (const sl_sim::SceneFileError&)
  {
    return 0;  // refused, naming the file: the documented error path
  }
  FUZZ_CHECK(!scene.objects.empty());
  for (const sl_sim::SceneObject& o : scene.objects)
  {
    sl_sim::validateObject(o);  // std::invalid_argument here is a finding
    (void)o.worldBounds();
    if (o.type == sl_sim::ObjectType::Plane && o.material.texture.type == sl_sim::TextureType::Checkerboard)
    {
      const auto corners = sl_sim::checkerboardInnerCorners(o);
      FUZZ_CHECK(corners.size() == static_cast<size_t>((o.material.texture.cols - 1) * (o.material.texture.rows - 1)));
    }
  }
  // A fan of rays from where a robot's camera would be.
  for (int i = 0; i < 16; ++i)
  {
    sl_sim::Ray ray;
    ray.origin = Eigen::Vector3d(0.0, 0.0, 0.1);
    const double a = -0.8 + 0.1 * i;
    ray.direction = Eigen::Vector3d(std::cos(a), std::sin(a), -0.05 * (i % 4));
    sl_sim::Hit hit;
    if (sl_sim::intersectScene(scene, ray, hit))
    {
      FUZZ_CHECK(hit.object >= 0 && static_cast<size_t>(hit.object) < scene.objects.size());
      FUZZ_CHECK(hit.t > 0.0 && !std::isnan(hit.t));
    }
  }
  return 0;
}
