// The renderer, stage 1: scene objects moved into the camera frame and culled against the tiles
// of the camera and of the projector frame (for shadow rays), in two levels (64 px, then 16 px).
#include "renderer_impl.h"

#include <stdexcept>
#include <string>

namespace sl_sim
{
// The renderer's internal types, constants and kernels.
using namespace sim;

namespace
{
sim::KObject kernelObject(const sim::PreparedObject<float>& g, const Vec3f& origin)
{
  sim::KObject k;
  k.type = static_cast<int>(g.type);
  k.id = g.index;
  k.infinite = g.infinite ? 1 : 0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      k.a[3 * c + r] = g.axes(r, c);
  const Vec3f o = g.toLocal(origin);
  for (int i = 0; i < 3; ++i)
  {
    k.o[i] = o[i];
    k.h[i] = g.half[i];
  }
  return k;
}
}  // namespace

void Renderer::Impl::prepareScene(const Scene& scene, const Eigen::Isometry3d& camera_in_world)
{
  if (scene.objects.size() > kMaxObjects)
    throw std::invalid_argument("scene: more than " + std::to_string(kMaxObjects) + " objects");
  const Eigen::Isometry3d world_to_camera = camera_in_world.inverse();
  objects.resize(scene.objects.size());
  if (obj_mark.size() < objects.size())
    obj_mark.assign(objects.size(), 0);
  for (size_t i = 0; i < scene.objects.size(); ++i)
  {
    const SceneObject& so = scene.objects[i];
    RenderObject& o = objects[i];
    o.g.set(so, world_to_camera * so.pose, static_cast<int>(i));
    o.cam = kernelObject(o.g, Vec3f::Zero());
    o.proj = kernelObject(o.g, Cp);
    const Material& m = so.material;
    sim::KSurface& s = o.surf;
    s.g = o.cam;
    s.texture = static_cast<int>(m.texture.type);
    s.albedo = static_cast<float>(m.albedo);
    s.inv_scale = static_cast<float>(1.0 / m.texture.scale);
    s.contrast = static_cast<float>(m.texture.contrast);
    s.off_u = static_cast<float>(hash32(static_cast<uint32_t>(i) * 2 + 1) % kTextureSize);
    s.off_v = static_cast<float>(hash32(static_cast<uint32_t>(i) * 2 + 2) % kTextureSize);
    s.cols = m.texture.cols;
    s.rows = m.texture.rows;
    s.inv_square = static_cast<float>(1.0 / m.texture.square);
    s.half_w = static_cast<float>(m.texture.cols * m.texture.square / 2);
    s.half_h = static_cast<float>(m.texture.rows * m.texture.square / 2);
    s.dark_albedo = static_cast<float>(m.texture.dark_albedo);
    o.specular = static_cast<float>(m.specular);
    o.shininess = static_cast<float>(m.shininess);
    o.spec_norm = static_cast<float>(m.specular * (m.shininess + 8.0) / 8.0);
  }
}

// Whether an object can meet a ray of the frustum.
bool Renderer::Impl::inside(const RenderObject& o, const Frustum& f)
{
  if (o.g.infinite)
  {
    // An infinite plane is met by some ray of the pyramid iff some corner ray heads towards it.
    const Vec3f n = o.g.axes.col(2);
    const float side = n.dot(f.apex) - n.dot(o.g.centre);
    if (std::abs(side) < 1e-7f)
      return true;
    for (const Vec3f& c : f.corner)
      if (n.dot(c) * side < 0.f)
        return true;
    return false;
  }
  for (size_t i = 0; i < 4; ++i)
    if (o.g.support(f.n[i]) < f.d[i] - 1e-5f)
      return false;
  return true;
}

// The smallest depth (along the frustum's axis) of the part of an object the frustum can see, or
// less: a bound to skip objects behind everything the rays have already hit.
float Renderer::Impl::nearDepth(const RenderObject& o, const Frustum& f)
{
  if (o.g.infinite)
  {
    // Along each ray the depth to the plane is c / (n . r): over the pyramid it is smallest at a
    // corner (among the corners whose rays meet the plane).
    const Vec3f n = o.g.axes.col(2);
    const float c = n.dot(o.g.centre) - n.dot(f.apex);
    float best = kInf;
    for (const Vec3f& r : f.corner)
    {
      const float s = c / n.dot(r);
      if (s > 0.f)
        best = std::min(best, s);
    }
    return std::isfinite(best) ? best : 0.f;
  }
  return -o.g.support(-f.axis) - f.axis.dot(f.apex);
}

void Renderer::Impl::cull(TileLists& tl)
{
  const int n = static_cast<int>(objects.size());
  if (tl.stride != n)
  {
    tl.stride = n;
    tl.lists.assign(tl.fine.size() * static_cast<size_t>(std::max(n, 1)), 0);
    tl.near.assign(tl.lists.size(), 0.f);
    tl.coarse_lists.assign(tl.coarse.size() * static_cast<size_t>(std::max(n, 1)), 0);
    tl.coarse_near.assign(tl.coarse_lists.size(), 0.f);
  }
  // Sorted insertion by near depth.
  auto insert = [](uint16_t* list, float* near, int& count, uint16_t k, float d)
  {
    int pos = count++;
    while (pos > 0 && near[pos - 1] > d)
    {
      near[pos] = near[pos - 1];
      list[pos] = list[pos - 1];
      --pos;
    }
    near[pos] = d;
    list[pos] = k;
  };
  for (size_t c = 0; c < tl.coarse.size(); ++c)
  {
    int count = 0;
    uint16_t* list = tl.coarse_lists.data() + c * static_cast<size_t>(n);
    float* near = tl.coarse_near.data() + c * static_cast<size_t>(n);
    for (int k = 0; k < n; ++k)
      if (inside(objects[static_cast<size_t>(k)], tl.coarse[c]))
        insert(list, near, count, static_cast<uint16_t>(k), nearDepth(objects[static_cast<size_t>(k)], tl.coarse[c]));
    tl.coarse_counts[c] = count;
  }
  for (int ty = 0; ty < tl.ny; ++ty)
    for (int tx = 0; tx < tl.nx; ++tx)
    {
      const size_t t = static_cast<size_t>(ty) * tl.nx + tx;
      const size_t c = static_cast<size_t>(ty / kCoarse) * tl.cnx + tx / kCoarse;
      int count = 0;
      uint16_t* list = tl.lists.data() + t * static_cast<size_t>(n);
      float* near = tl.near.data() + t * static_cast<size_t>(n);
      for (int j = 0; j < tl.coarse_counts[c]; ++j)
      {
        const uint16_t k = tl.coarse_lists[c * static_cast<size_t>(n) + static_cast<size_t>(j)];
        if (inside(objects[k], tl.fine[t]))
          insert(list, near, count, k, nearDepth(objects[k], tl.fine[t]));
      }
      tl.counts[t] = count;
    }
}

}  // namespace sl_sim
