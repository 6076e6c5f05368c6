#pragma once
// Internal: the renderer's state and its stages (renderer.cpp gives the overview), shared by the
// renderer_*.cpp files only.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "geometry.h"
#include "lanes.h"
#include "sl_sim/renderer.h"

namespace sl_sim
{
namespace sim
{
using Vec3f = Eigen::Vector3f;

constexpr int kTile = 16;               // fine tile, px (kTile * kTile = kLanes)
constexpr int kCoarse = 4;              // coarse tile = kCoarse x kCoarse fine tiles
constexpr int kPatternLevels = 11;      // sigma 0, then 0.3 * sqrt(2)^(k-1), k = 1..10 (up to 6.8 px)
constexpr float kPatternSigma1 = 0.3f;  // sigma of pattern level 1, projector px
constexpr int kPatternPad = 2;          // zero border of the pattern levels
constexpr int kLutSize = 4096;          // 12-bit linear signal -> 8-bit output
constexpr int kTextureSize = 256;       // tileable value-noise texture
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kPrimaryTMin = 1e-4f;  // m (camera rays have z = 1, so t is the depth)
constexpr float kShadowTMin = 1e-5f;   // fractions of the projector-to-point segment
constexpr float kShadowTMax = 1.f - 2e-4f;
constexpr size_t kMaxObjects = 2047;  // 11 bits of the anti-aliasing key
constexpr int kCameraLevels = 5;      // blur sigma 0, 0.5, 1, 2, 4 px
constexpr float kCameraTopSigma[kCameraLevels] = { 0.f, 0.5f, 1.f, 2.f, 4.f };
constexpr float kGlareSigma = 10.f;  // px

static_assert(kTile * kTile == kLanes, "a tile is one batch of lanes");

// A well-mixing 32-bit integer hash (xor-shift-multiply rounds).
inline uint32_t hash32(uint32_t x)
{
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

// A pyramid of rays from an apex: side planes (inside: n . x >= d) and corner rays.
struct Frustum
{
  std::array<Vec3f, 4> n;
  std::array<float, 4> d;
  std::array<Vec3f, 4> corner;  // corner rays, unit depth along `axis`
  Vec3f apex;
  Vec3f axis;  // the optical axis: depth is axis . (x - apex)
};

// A scene object in the camera frame: for culling, for the kernels (camera and projector origins)
// and for shading.
struct RenderObject
{
  sim::PreparedObject<float> g;
  sim::KObject cam;   // rays from the camera centre
  sim::KObject proj;  // rays from the projector centre
  sim::KSurface surf;
  float specular = 0.f;
  float shininess = 1.f;
  float spec_norm = 1.f;  // specular * (shininess + 8) / 8: the normalised lobe's peak
};

// Object lists of a grid of tiles.
struct TileLists
{
  int nx = 0, ny = 0, cnx = 0, cny = 0;
  std::vector<Frustum> fine, coarse;
  std::vector<uint16_t> lists;  // tile * stride + k, in order of increasing `near`
  std::vector<float> near;      // per list entry: the object's smallest depth in the tile
  std::vector<int> counts;
  std::vector<uint16_t> coarse_lists;  // in order of increasing `coarse_near`
  std::vector<float> coarse_near;
  std::vector<int> coarse_counts;
  int stride = -1;
};

// A normalised Gaussian kernel of 2 radius + 1 taps, for sim::blurImage().
struct Kernel
{
  std::vector<float> w;
  int radius = 0;
  void make(float sigma)
  {
    radius = std::min(31, std::max(1, static_cast<int>(std::ceil(3.f * sigma))));  // blurImage: r <= 31
    w.assign(static_cast<size_t>(2 * radius + 1), 0.f);
    float sum = 0.f;
    for (int i = -radius; i <= radius; ++i)
      sum += w[static_cast<size_t>(i + radius)] = std::exp(-0.5f * static_cast<float>(i * i) / (sigma * sigma));
    for (float& v : w)
      v /= sum;
  }
};

// A run of lanes [begin, end) whose rays all lie in camera tile `tile`.
struct Segment
{
  int begin, end;
  size_t tile;
};

// Structure-of-arrays buffers of one batch of rays.
struct alignas(64) Lanes
{
  alignas(64) float dx[kLanes];
  alignas(64) float dy[kLanes];
  alignas(64) float ones[kLanes];
  alignas(64) int32_t none[kLanes];  // -1: no object to skip
  alignas(64) float t[kLanes];
  alignas(64) float nx[kLanes];
  alignas(64) float ny[kLanes];
  alignas(64) float nz[kLanes];
  alignas(64) float albedo[kLanes];
  alignas(64) float u[kLanes];
  alignas(64) float v[kLanes];
  alignas(64) float e[kLanes];
  alignas(64) float level[kLanes];
  alignas(64) float sx[kLanes];
  alignas(64) float sy[kLanes];
  alignas(64) float sz[kLanes];
  alignas(64) float tsh[kLanes];
  alignas(64) float csig[kLanes];
  alignas(64) float pattern[kLanes];
  alignas(64) float direct[kLanes];
  alignas(64) float radiance[kLanes];
  alignas(64) float pz[kLanes];
  alignas(64) float tu[kLanes];
  alignas(64) float tv[kLanes];
  alignas(64) int32_t obj[kLanes];
  alignas(64) int32_t part[kLanes];
  alignas(64) int32_t parity[kLanes];
  alignas(64) int32_t lit[kLanes];
  alignas(64) int32_t shobj[kLanes];
  alignas(64) int32_t shpart[kLanes];
  int pixel[kLanes];  // target pixel of each lane
};

// Per-row table of a linear upsampling by `scale` (pixel centres aligned, edges clamped): output
// row y interpolates source rows y0[y] and y0[y] + 1 with weight fy[y] on the second.
struct UpsampleTable
{
  std::vector<int32_t> y0;
  std::vector<float> fy;
  void make(int h, int src_h, int scale)
  {
    y0.resize(static_cast<size_t>(h));
    fy.resize(static_cast<size_t>(h));
    for (int k = 0; k < h; ++k)
    {
      const float s = std::min(std::max((k + 0.5f) / scale - 0.5f, 0.f), static_cast<float>(src_h - 1));
      const int a = std::min(static_cast<int>(s), std::max(src_h - 2, 0));
      y0[static_cast<size_t>(k)] = a;
      fy[static_cast<size_t>(k)] = src_h > 1 ? s - static_cast<float>(a) : 0.f;
    }
  }
};

}  // namespace sim

struct Renderer::Impl
{
  sl_projector::Rig rig;
  SimSettings settings;
  int W = 0, H = 0, Wp = 0, Hp = 0;

  // Camera: pixel-centre rays (x, y, 1) on a grid with a one-pixel border.
  std::vector<float> ray_x, ray_y;
  int grid_w = 0;
  // The same pixel-centre rays in tile order (kLanes per tile, padded lanes repeat the first).
  std::vector<float> tile_dx, tile_dy;

  // Projector and optics for the kernels.
  sim::KProjector kp;
  sim::Vec3f Cp;
  float ambient = 0.f, black = 0.f;
  double proj_defocus_k = 0.0, cam_defocus_k = 0.0;

  // Pattern: the last frame buffer and its pyramid (kPatternLevels padded float levels in a row).
  cv::Mat pattern_copy;
  std::vector<uint32_t> pattern_levels;  // packed pairs, see sim::patternLanes()
  int level_w = 0, level_h = 0, level_size = 0;

  // Tables.
  std::vector<float> vignette;  // per pixel, exposure folded in
  std::vector<int32_t> lut;     // output curve
  std::vector<float> texture;   // tileable value noise in [0, 1]

  // Per frame.
  std::vector<sim::RenderObject> objects;
  sim::TileLists cam_tiles, proj_tiles;
  std::unique_ptr<sim::Lanes> lanes;
  std::vector<uint32_t> obj_mark;
  std::vector<sim::Segment> segments;  // of an anti-aliasing batch
  uint32_t mark = 0;
  std::vector<uint16_t> hit_list, shadow_list;
  std::vector<uint16_t> keys;
  std::vector<uint8_t> edge;
  std::vector<int> edge_pixels;
  float max_sigma = 0.f;
  // Camera blur levels at full resolution, one after the other (0: the radiance), and scratch.
  std::vector<float> levels;
  std::vector<float> rows_half, rows_quarter, rows_halo;  // low-resolution rows upsampled horizontally
  int row_stride = 0;
  std::vector<float> half_in, half_blur, quarter_in, quarter_blur, quarter_halo, tmp, row;
  int hw = 0, hh = 0, qw = 0, qh = 0;
  sim::Kernel k1, k2, k3, k4, kglare;
  sim::UpsampleTable up_half, up_quarter;
  std::vector<std::array<float, 2>> aa_offsets;  // extra rays of an edge pixel, px from its centre
  bool aa_with_centre = false;                   // the centre sample counts as one of them
  struct AaRay
  {
    std::ptrdiff_t offset;  // grid index of the top-left neighbour, relative to the pixel's
    float w[4];             // bilinear weights: top-left, top-right, bottom-left, bottom-right
  };
  std::vector<AaRay> aa_rays;

  // Set-up (renderer_setup.cpp): camera rays and tiles, projector optics, tables, buffers.
  Impl(const sl_projector::Rig& r, const SimSettings& s);
  void buildCamera();
  void buildProjector();
  template <typename RayFn>
  void makeTiles(sim::TileLists& tl, int width, int height, double pad, RayFn ray, const Eigen::Vector3d& apex,
                 const Eigen::Vector3d& axis);
  void buildTables();
  void allocateFrameBuffers();
  void makeCameraBlurKernels();
  void makeAntialiasRays();
  // The pattern pyramid, rebuilt when the projector frame changes (renderer_setup.cpp).
  void updatePattern(const cv::Mat& pattern);

  // Stage 1 (renderer_cull.cpp): scene objects into the camera frame, culled per tile.
  void prepareScene(const Scene& scene, const Eigen::Isometry3d& camera_in_world);
  static bool inside(const sim::RenderObject& o, const sim::Frustum& f);
  static float nearDepth(const sim::RenderObject& o, const sim::Frustum& f);
  void cull(sim::TileLists& tl);

  // Stages 2 and 3 (renderer_trace.cpp): rays per tile through the kernels, anti-aliasing of edges.
  uint32_t nextMark();
  void trace(sim::Lanes& b, const float* dx, const float* dy, int n, const sim::Segment* segments, int n_segments);
  // The steps of trace().
  void findNearestHits(sim::Lanes& b, const float* dx, const float* dy, int n, const sim::Segment* segments,
                       int n_segments);
  void shadeSurfaces(sim::Lanes& b, const float* dx, const float* dy, int n);
  void castShadowRays(sim::Lanes& b, int n);
  void gatherOccluders(const float* box, uint32_t mark);
  void addRadiance(sim::Lanes& b, const float* dx, const float* dy, int n);
  void castPrimary(RenderOutput& out);
  void antialias();
  void queueEdgeRays(int tx, int ty, int& n);
  void traceAntialiasBatch(int& n);

  // Stages 4 and 5 (renderer_sensor.cpp): camera defocus and glare, then the sensor.
  int cameraLevelsNeeded() const;
  float* level(int k) { return levels.data() + static_cast<size_t>(k) * W * H; }
  void blurCamera(int n_levels, bool need_glare);
  void sensor(uint64_t seed, const cv::Mat& depth, cv::Mat& image);
};

}  // namespace sl_sim
