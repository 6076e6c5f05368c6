// The renderer, stages 2 and 3: per camera tile one ray per pixel centre, traced as lanes through
// the kernels (lanes.h): nearest hit, surface, projector side, shadow rays, pattern lookup, radiance;
// then more rays for the pixels on edges (anti-aliasing).
#include "renderer_impl.h"

#include <cstring>

namespace sl_sim
{
// The renderer's internal types, constants and kernels.
using namespace sim;

uint32_t Renderer::Impl::nextMark()
{
  if (++mark == 0)
  {
    std::fill(obj_mark.begin(), obj_mark.end(), 0);
    mark = 1;
  }
  return mark;
}

// Traces n lanes (a multiple of 8) with rays (dx, dy, 1); segments cover lanes 0..n-1, each
// intersected with its own tile's objects. Fills b's t/obj/part, u/v (NaN where unlit), lit, csig
// and radiance.
void Renderer::Impl::trace(Lanes& b, const float* dx, const float* dy, int n, const Segment* segments, int n_segments)
{
  findNearestHits(b, dx, dy, n, segments, n_segments);
  shadeSurfaces(b, dx, dy, n);
  sim::projectLanes(kp, dx, dy, b.t, b.obj, b.nx, b.ny, b.nz, n, b.u, b.v, b.e, b.level, b.sx, b.sy, b.sz, b.lit,
                    b.csig, b.pz);
  castShadowRays(b, n);
  addRadiance(b, dx, dy, n);
}

void Renderer::Impl::findNearestHits(Lanes& b, const float* dx, const float* dy, int n, const Segment* segments,
                                     int n_segments)
{
  std::fill(b.t, b.t + n, kInf);
  std::fill(b.obj, b.obj + n, -1);
  std::fill(b.part, b.part + n, 0);
  // Per segment, objects nearest first, stopping at the first one that lies behind every lane's
  // hit so far. hit_list: the objects that were the nearest hit of some lane at some point (a
  // superset of those that still are).
  const uint32_t hm = nextMark();
  hit_list.clear();
  for (int sgi = 0; sgi < n_segments; ++sgi)
  {
    const Segment& sg = segments[sgi];
    const int len = sg.end - sg.begin;
    const int count = cam_tiles.counts[sg.tile];
    const uint16_t* list = cam_tiles.lists.data() + sg.tile * cam_tiles.stride;
    const float* near = cam_tiles.near.data() + sg.tile * cam_tiles.stride;
    float farthest = kInf;
    for (int k = 0; k < count && near[k] < farthest; ++k)
    {
      if (sim::intersectLanes(objects[list[k]].cam, dx + sg.begin, dy + sg.begin, b.ones, len, kPrimaryTMin,
                              b.t + sg.begin, b.obj + sg.begin, b.part + sg.begin, b.none) &&
          obj_mark[list[k]] != hm)
      {
        obj_mark[list[k]] = hm;
        hit_list.push_back(list[k]);
      }
      if (k + 1 < count)
        farthest = sim::maxLanes(b.t + sg.begin, len);
    }
  }
}

void Renderer::Impl::shadeSurfaces(Lanes& b, const float* dx, const float* dy, int n)
{
  // Lanes that hit nothing keep albedo 0 (no light); their other surface values are not used.
  std::fill(b.albedo, b.albedo + n, 0.f);
  std::fill(b.parity, b.parity + n, 0);
  for (uint16_t k : hit_list)
  {
    const sim::KSurface& surf = objects[k].surf;
    sim::surfaceLanes(surf, dx, dy, b.t, b.obj, b.part, n, b.nx, b.ny, b.nz, b.albedo, b.parity, b.tu, b.tv);
    if (surf.texture == static_cast<int>(TextureType::Noise))
      sim::noiseLanes(k, surf.contrast, texture.data(), b.obj, b.tu, b.tv, n, b.albedo);
  }
}

// Shadow rays from the projector centre to the lit points, against the objects of the projector
// tiles those points fall in.
void Renderer::Impl::castShadowRays(Lanes& b, int n)
{
  const uint32_t pm = nextMark();
  shadow_list.clear();
  float box[5];
  const bool any_lit = sim::litBounds(b.u, b.v, b.lit, b.pz, n, box);
  if (any_lit && settings.shadows)  // with shadows off no occluder is gathered
    gatherOccluders(box, pm);
  if (any_lit && !shadow_list.empty())
  {
    for (int i = 0; i < n; ++i)
      b.tsh[i] = b.lit[i] ? kShadowTMax : -1.f;
    for (uint16_t k : shadow_list)
      sim::intersectLanes(objects[k].proj, b.sx, b.sy, b.sz, n, kShadowTMin, b.tsh, b.shobj, b.shpart, b.obj);
    sim::shadowLanes(b.tsh, kShadowTMax, n, b.lit, b.u, b.v);
  }
}

// The objects of the projector tiles overlapping the bounding box of the lit lanes' projector
// pixels (box as sim::litBounds()), into shadow_list.
void Renderer::Impl::gatherOccluders(const float* box, uint32_t mark)
{
  const int tx0 = std::min(proj_tiles.nx - 1, static_cast<int>((box[0] + 0.5f) * (1.f / kTile)));
  const int tx1 = std::min(proj_tiles.nx - 1, static_cast<int>((box[1] + 0.5f) * (1.f / kTile)));
  const int ty0 = std::min(proj_tiles.ny - 1, static_cast<int>((box[2] + 0.5f) * (1.f / kTile)));
  const int ty1 = std::min(proj_tiles.ny - 1, static_cast<int>((box[3] + 0.5f) * (1.f / kTile)));
  const float deepest = box[4];  // occluders lie in front of the points they shadow
  for (int ty = ty0; ty <= ty1; ++ty)
    for (int tx = tx0; tx <= tx1; ++tx)
    {
      const size_t pt = static_cast<size_t>(ty) * proj_tiles.nx + tx;
      const uint16_t* pl = proj_tiles.lists.data() + pt * proj_tiles.stride;
      const float* pn = proj_tiles.near.data() + pt * proj_tiles.stride;
      for (int j = 0; j < proj_tiles.counts[pt] && pn[j] < deepest; ++j)
        if (obj_mark[pl[j]] != mark)
        {
          obj_mark[pl[j]] = mark;
          shadow_list.push_back(pl[j]);
        }
    }
}

// Pattern lookup, radiance (ambient plus projector light) and the specular lobes of the hit objects.
void Renderer::Impl::addRadiance(Lanes& b, const float* dx, const float* dy, int n)
{
  sim::patternLanes(pattern_levels.data(), level_size, level_w, kPatternPad, b.u, b.v, b.level, b.lit, n, b.pattern);
  sim::radianceLanes(ambient, black, b.albedo, b.e, b.pattern, b.lit, n, b.direct, b.radiance);
  for (uint16_t k : hit_list)
  {
    const RenderObject& o = objects[k];
    if (o.specular > 0.f)
      sim::specularLanes(k, o.spec_norm, o.shininess, dx, dy, b.sx, b.sy, b.sz, b.nx, b.ny, b.nz, b.obj, b.direct, n,
                         b.radiance);
  }
}

void Renderer::Impl::castPrimary(RenderOutput& out)
{
  Lanes& b = *lanes;
  max_sigma = 0.f;
  float* radiance = levels.data();
  for (int ty = 0; ty < cam_tiles.ny; ++ty)
    for (int tx = 0; tx < cam_tiles.nx; ++tx)
    {
      const int x0 = tx * kTile, y0 = ty * kTile;
      const int tw = std::min(kTile, W - x0), th = std::min(kTile, H - y0);
      const int n = tw * th;
      const int npad = (n + 7) & ~7;
      const int tile = ty * cam_tiles.nx + tx;
      const Segment whole{ 0, npad, static_cast<size_t>(tile) };
      trace(b, tile_dx.data() + static_cast<size_t>(tile) * kLanes, tile_dy.data() + static_cast<size_t>(tile) * kLanes,
            npad, &whole, 1);
      const size_t p0 = static_cast<size_t>(y0) * W + x0;
      max_sigma = std::max(
          max_sigma,
          sim::storeTile(th, tw, b.radiance, b.t, b.obj, b.part, b.lit, b.parity, b.u, b.v, b.csig, radiance + p0,
                         out.depth.ptr<float>(y0) + x0, out.projector_coords.ptr<float>(y0) + 2 * x0, keys.data() + p0,
                         W, static_cast<int>(out.depth.step1()), static_cast<int>(out.projector_coords.step1())));
    }
}

// Pixels on edges (object, face, shadow, texture square) get more rays: the centre sample plus
// aa_offsets, averaged. The rays of the edge pixels of consecutive tiles fill batches of lanes;
// each tile's rays form a segment traced against that tile's objects.
void Renderer::Impl::antialias()
{
  if (aa_offsets.empty())
    return;
  sim::markEdges(keys.data(), W, H, edge.data());
  edge_pixels.clear();
  int n = 0;
  segments.clear();
  for (int ty = 0; ty < cam_tiles.ny; ++ty)
    for (int tx = 0; tx < cam_tiles.nx; ++tx)
      queueEdgeRays(tx, ty, n);
  traceAntialiasBatch(n);
}

// Queues the sub-pixel rays of the edge pixels of camera tile (tx, ty) as one segment of the batch
// (n lanes so far), tracing the batch whenever it is full.
void Renderer::Impl::queueEdgeRays(int tx, int ty, int& n)
{
  Lanes& b = *lanes;
  const int extra = static_cast<int>(aa_offsets.size());
  const size_t tile = static_cast<size_t>(ty) * cam_tiles.nx + tx;
  const int x0 = tx * kTile, y0 = ty * kTile;
  const int tw = std::min(kTile, W - x0), th = std::min(kTile, H - y0);
  bool open = false;  // a segment for this tile is open in the batch
  for (int v = y0; v < y0 + th; ++v)
  {
    const uint8_t* e = edge.data() + static_cast<size_t>(v) * W + x0;
    if (tw == kTile)
    {
      uint64_t w0, w1;
      std::memcpy(&w0, e, sizeof w0);
      std::memcpy(&w1, e + 8, sizeof w1);
      if ((w0 | w1) == 0)
        continue;
    }
    for (int c = 0; c < tw; ++c)
    {
      if (!e[c])
        continue;
      const int u = x0 + c;
      const size_t p = static_cast<size_t>(v) * W + u;
      edge_pixels.push_back(static_cast<int>(p));
      if (n + extra > kLanes)
      {
        traceAntialiasBatch(n);
        open = false;
      }
      if (!open)
      {
        segments.push_back(Segment{ n, n, tile });
        open = true;
      }
      // Sub-pixel rays: bilinear in the grid of pixel-centre rays (the distortion is smooth).
      const size_t g0 = static_cast<size_t>(v + 1) * grid_w + (u + 1);
      for (const AaRay& a : aa_rays)
      {
        const size_t g = g0 + a.offset;
        b.dx[n] =
            a.w[0] * ray_x[g] + a.w[1] * ray_x[g + 1] + a.w[2] * ray_x[g + grid_w] + a.w[3] * ray_x[g + grid_w + 1];
        b.dy[n] =
            a.w[0] * ray_y[g] + a.w[1] * ray_y[g + 1] + a.w[2] * ray_y[g + grid_w] + a.w[3] * ray_y[g + grid_w + 1];
        b.pixel[n] = static_cast<int>(p);
        ++n;
      }
      segments.back().end = n;
    }
  }
}

// Traces the n queued rays and averages each pixel's rays into its radiance; empties the batch.
void Renderer::Impl::traceAntialiasBatch(int& n)
{
  if (n == 0)
    return;
  Lanes& b = *lanes;
  float* radiance = levels.data();
  const int extra = static_cast<int>(aa_offsets.size());
  const float weight = 1.f / static_cast<float>(extra + (aa_with_centre ? 1 : 0));
  const int npad = (n + 7) & ~7;
  for (int i = n; i < npad; ++i)
  {
    b.dx[i] = b.dx[0];
    b.dy[i] = b.dy[0];
  }
  segments.back().end = npad;  // the padding lanes repeat lane 0: any tile's objects will do
  trace(b, b.dx, b.dy, npad, segments.data(), static_cast<int>(segments.size()));
  for (int i = 0; i < n; i += extra)
  {
    float sum = 0.f;
    for (int j = 0; j < extra; ++j)
      sum += b.radiance[i + j];
    float& r = radiance[static_cast<size_t>(b.pixel[i])];
    r = (aa_with_centre ? r + sum : sum) * weight;
  }
  n = 0;
  segments.clear();
}

}  // namespace sl_sim
