// The projector-camera renderer. Everything happens in the camera optical frame:
//  1. scene objects are moved into the camera frame and culled against 16 x 16 pixel tiles of the
//     camera, and of the projector frame (for shadow rays), in two levels (64 px, then 16 px);
//  2. per camera tile, one ray per pixel centre, traced as 256 "lanes" through data-parallel kernels
//     (lanes.h): nearest hit, surface (normal, albedo, texture), projector side (pixel, irradiance
//     P cos / d^2 with lens falloff, pattern blur from defocus and footprint), shadow rays to the
//     projector centre, trilinear lookup in the pre-blurred pattern pyramid, radiance with ambient
//     light and a Blinn-Phong lobe. This gives depth, projector coordinates and a radiance sample;
//  3. pixels on edges (object, face, shadow, texture square) get `antialias` rays;
//  4. camera defocus: blur levels of the radiance image (sigma 0.5 and 1 px at full, 2 px at half
//     and 4 px at quarter resolution) blended per pixel by depth; glare halo;
//  5. vignetting, exposure, shot and read noise (approximately Gaussian, from a seeded hash of the
//     pixel index), 12-bit quantisation, gamma, 8-bit output with saturation.
// All buffers are allocated in the constructor or on the first frame.
#include "sl_sim/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "geometry.h"
#include "lanes.h"

namespace sl_sim
{

namespace
{
using Vec3f = Eigen::Vector3f;
using sim::kLanes;

constexpr int kTile = 16;               // fine tile, px (kTile * kTile = kLanes)
constexpr int kCoarse = 4;              // coarse tile = kCoarse x kCoarse fine tiles
constexpr int kPatternLevels = 11;      // sigma 0, then 0.3 * sqrt(2)^(k-1), k = 1..10 (up to 6.8 px)
constexpr float kPatternSigma1 = 0.3f;  // sigma of pattern level 1, projector px
constexpr int kPatternPad = 2;          // zero border of the pattern levels
constexpr int kLutSize = 4096;          // 12-bit linear signal -> 8-bit output
constexpr int kTextureSize = 256;       // tileable value-noise texture
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
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

// 64-bit mixing (the user's seed -> frame keys).
inline uint64_t mix64(uint64_t z)
{
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
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

Frustum makeFrustum(const Eigen::Vector3d& apex, const Eigen::Vector3d& axis, const Eigen::Vector3d& r00,
                    const Eigen::Vector3d& r10, const Eigen::Vector3d& r01, const Eigen::Vector3d& r11)
{
  const Eigen::Vector3d centre = r00.normalized() + r10.normalized() + r01.normalized() + r11.normalized();
  const std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 4> edges = {
    { { r00, r01 }, { r00, r10 }, { r10, r11 }, { r01, r11 } }
  };
  Frustum f;
  for (int i = 0; i < 4; ++i)
  {
    Eigen::Vector3d n = edges[static_cast<size_t>(i)].first.cross(edges[static_cast<size_t>(i)].second).normalized();
    if (n.dot(centre) < 0.0)
      n = -n;
    f.n[static_cast<size_t>(i)] = n.cast<float>();
    f.d[static_cast<size_t>(i)] = static_cast<float>(n.dot(apex));
  }
  f.corner = { r00.cast<float>(), r10.cast<float>(), r01.cast<float>(), r11.cast<float>() };
  f.apex = apex.cast<float>();
  f.axis = axis.cast<float>();
  return f;
}

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
}  // namespace

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
  Vec3f Cp;
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
  std::vector<RenderObject> objects;
  TileLists cam_tiles, proj_tiles;
  std::unique_ptr<Lanes> lanes;
  std::vector<uint32_t> obj_mark;
  std::vector<Segment> segments;  // of an anti-aliasing batch
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
  Kernel k1, k2, k3, k4, kglare;
  UpsampleTable up_half, up_quarter;
  std::vector<std::array<float, 2>> aa_offsets;  // extra rays of an edge pixel, px from its centre
  bool aa_with_centre = false;                   // the centre sample counts as one of them
  struct AaRay
  {
    std::ptrdiff_t offset;  // grid index of the top-left neighbour, relative to the pixel's
    float w[4];             // bilinear weights: top-left, top-right, bottom-left, bottom-right
  };
  std::vector<AaRay> aa_rays;

  Impl(const sl_projector::Rig& r, const SimSettings& s) : rig(r), settings(s)
  {
    settings.validate();
    try
    {
      rig.validate();
    }
    catch (const std::invalid_argument& e)
    {
      throw std::invalid_argument(std::string("rig: ") + e.what());
    }
    W = rig.camera.width;
    H = rig.camera.height;
    Wp = rig.projector.width;
    Hp = rig.projector.height;
    buildCamera();
    buildProjector();
    buildTables();
    lanes.reset(new Lanes());
    segments.reserve(kLanes);
    std::fill(std::begin(lanes->ones), std::end(lanes->ones), 1.f);
    std::fill(std::begin(lanes->none), std::end(lanes->none), -1);
    const size_t n = static_cast<size_t>(W) * H;
    keys.assign(n, 0);
    edge.assign(n, 0);
    edge_pixels.reserve(n);
    levels.assign(n * kCameraLevels, 0.f);
    hw = (W + 1) / 2;
    hh = (H + 1) / 2;
    qw = (hw + 1) / 2;
    qh = (hh + 1) / 2;
    half_in.assign(static_cast<size_t>(hw) * hh, 0.f);
    half_blur.assign(half_in.size(), 0.f);
    quarter_in.assign(static_cast<size_t>(qw) * qh, 0.f);
    quarter_blur.assign(quarter_in.size(), 0.f);
    quarter_halo.assign(quarter_in.size(), 0.f);
    tmp.assign(n, 0.f);
    row.assign(static_cast<size_t>(W + 256), 0.f);
    up_half.make(H, hh, 2);
    up_quarter.make(H, qh, 4);
    row_stride = 4 * qw;  // >= 2 hw >= W
    rows_half.assign(static_cast<size_t>(hh) * row_stride, 0.f);
    rows_quarter.assign(static_cast<size_t>(qh) * row_stride, 0.f);
    rows_halo.assign(static_cast<size_t>(qh) * row_stride, 0.f);
    // Incremental blurs (variances add): 0 -> 0.5 -> 1 px at full resolution; to 2 px at half
    // resolution after a 2 x 2 box (1/3 px^2) and before bilinear upsampling (2/3 px^2); to 4 px at
    // quarter resolution likewise (box 4/3, upsampling 8/3 full px^2). Kernel sigmas in the
    // resolution they run at.
    k1.make(0.5f);
    k2.make(std::sqrt(1.f - 0.25f));
    k3.make(std::sqrt(4.f - 1.f - 1.f / 3.f - 2.f / 3.f) / 2.f);
    k4.make(std::sqrt(16.f - (4.f - 2.f / 3.f) - 4.f / 3.f - 8.f / 3.f) / 4.f);
    kglare.make(std::sqrt(kGlareSigma * kGlareSigma - (4.f - 2.f / 3.f) - 4.f / 3.f - 8.f / 3.f) / 4.f);
    if (settings.antialias == 4)
    {
      // The centre sample and three more on a circle of 0.4 px, 120 degrees apart (rotated off the
      // pixel axes): four samples for three new rays.
      aa_with_centre = true;
      for (int k = 0; k < 3; ++k)
      {
        const float a = static_cast<float>((15.0 + 120.0 * k) * M_PI / 180.0);
        aa_offsets.push_back({ 0.4f * std::cos(a), 0.4f * std::sin(a) });
      }
    }
    else if (settings.antialias == 16)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
          aa_offsets.push_back({ (i + 0.5f) / 4.f - 0.5f, (j + 0.5f) / 4.f - 0.5f });
    for (const auto& off : aa_offsets)
    {
      const int ix = off[0] < 0.f ? -1 : 0, iy = off[1] < 0.f ? -1 : 0;
      const float fx = off[0] - ix, fy = off[1] - iy;
      aa_rays.push_back({ static_cast<std::ptrdiff_t>(iy) * grid_w + ix,
                          { (1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy } });
    }
  }

  void buildCamera()
  {
    grid_w = W + 2;
    ray_x.resize(static_cast<size_t>(grid_w) * (H + 2));
    ray_y.resize(ray_x.size());
    for (int v = -1; v <= H; ++v)
      for (int u = -1; u <= W; ++u)
      {
        const Eigen::Vector3d r = rig.camera.ray(Eigen::Vector2d(u, v));
        const size_t i = static_cast<size_t>(v + 1) * grid_w + (u + 1);
        ray_x[i] = static_cast<float>(r.x());
        ray_y[i] = static_cast<float>(r.y());
      }
    const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile;
    tile_dx.assign(static_cast<size_t>(tiles_x) * tiles_y * kLanes, 0.f);
    tile_dy.assign(tile_dx.size(), 0.f);
    for (int ty = 0; ty < tiles_y; ++ty)
      for (int tx = 0; tx < tiles_x; ++tx)
      {
        const int x0 = tx * kTile, y0 = ty * kTile;
        const int tw = std::min(kTile, W - x0), th = std::min(kTile, H - y0);
        float* dx = tile_dx.data() + static_cast<size_t>(ty * tiles_x + tx) * kLanes;
        float* dy = tile_dy.data() + static_cast<size_t>(ty * tiles_x + tx) * kLanes;
        for (int i = 0; i < kLanes; ++i)
        {
          const int k = i < tw * th ? i : 0;
          const size_t g = static_cast<size_t>(y0 + k / tw + 1) * grid_w + (x0 + k % tw + 1);
          dx[i] = ray_x[g];
          dy[i] = ray_y[g];
        }
      }
    // Tiles padded by one pixel: anti-aliasing rays stay within +-0.5 px of their pixel.
    makeTiles(
        cam_tiles, W, H, 1.0, [this](double u, double v) { return rig.camera.ray(Eigen::Vector2d(u, v)); },
        Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  }

  void buildProjector()
  {
    const SimSettings& s = settings;
    const Eigen::Matrix3d R = rig.projector_pose.rotation;
    const Eigen::Vector3d t = rig.projector_pose.translation;
    const Eigen::Matrix3d Rt = R.transpose();
    const Eigen::Vector3d tt = -(Rt * t);
    for (int r = 0; r < 3; ++r)
    {
      for (int c = 0; c < 3; ++c)
        kp.r[3 * r + c] = static_cast<float>(Rt(r, c));
      kp.tr[r] = static_cast<float>(tt[r]);
      kp.c[r] = static_cast<float>(t[r]);
    }
    Cp = t.cast<float>();
    const sl_projector::PinholeModel& P = rig.projector;
    kp.fx = static_cast<float>(P.fx);
    kp.fy = static_cast<float>(P.fy);
    kp.cx = static_cast<float>(P.cx);
    kp.cy = static_cast<float>(P.cy);
    kp.k1 = static_cast<float>(P.dist[0]);
    kp.k2 = static_cast<float>(P.dist[1]);
    kp.p1 = static_cast<float>(P.dist[2]);
    kp.p2 = static_cast<float>(P.dist[3]);
    kp.k3 = static_cast<float>(P.dist[4]);
    kp.umax = Wp - 0.5f;
    kp.vmax = Hp - 0.5f;
    kp.frame_cx = (Wp - 1) / 2.f;
    kp.frame_cy = (Hp - 1) / 2.f;
    kp.inv_half_diag2 = 1.f / (kp.frame_cx * kp.frame_cx + kp.frame_cy * kp.frame_cy + 1e-6f);
    kp.falloff = static_cast<float>(1.0 - s.projector_vignetting);
    kp.power_focus2 = static_cast<float>(s.projector_power * s.projector_focus_distance * s.projector_focus_distance);
    kp.falloff_weight = s.irradiance_falloff ? 1.f : 0.f;
    kp.flat_power = s.irradiance_falloff ? 0.f : static_cast<float>(s.projector_power);
    // Thin lens: the blur circle's diameter on the sensor, in px, is
    //   A f_px z_f / (z_f - f) |1/z - 1/z_f|, aperture A = f / N, focal length f = f_px * pitch;
    // a disc of diameter b has the second moment of a Gaussian of sigma b / 4.
    auto defocusK = [](double f_px, double pitch, double n, double focus)
    {
      const double f = f_px * pitch;
      return (f / n) * f_px * focus / std::max(focus - f, 1e-6) / 4.0;
    };
    const double pf = std::sqrt(P.fx * P.fy);
    const double cf = std::sqrt(rig.camera.fx * rig.camera.fy);
    proj_defocus_k =
        s.defocus ? defocusK(pf, s.projector_pixel_size, s.projector_f_number, s.projector_focus_distance) : 0.0;
    cam_defocus_k = s.defocus ? defocusK(cf, s.camera_pixel_size, s.camera_f_number, s.camera_focus_distance) : 0.0;
    kp.defocus_k = static_cast<float>(proj_defocus_k);
    kp.inv_focus = static_cast<float>(1.0 / s.projector_focus_distance);
    kp.base2 = static_cast<float>(s.projector_base_blur * s.projector_base_blur);
    kp.footprint_k = static_cast<float>(pf / cf);
    kp.cam_defocus_k = static_cast<float>(cam_defocus_k);
    kp.cam_inv_focus = static_cast<float>(1.0 / s.camera_focus_distance);
    kp.cam_base2 = static_cast<float>(s.camera_base_blur * s.camera_base_blur);
    kp.sigma1 = kPatternSigma1;
    kp.max_level = static_cast<float>(kPatternLevels - 1);
    ambient = static_cast<float>(s.ambient);
    black = static_cast<float>(s.projector_black_level);
    makeTiles(
        proj_tiles, Wp, Hp, 0.5,
        [this, R](double u, double v) { return Eigen::Vector3d(R * rig.projector.ray(Eigen::Vector2d(u, v))); }, t,
        R.col(2));
  }

  template <typename RayFn>
  void makeTiles(TileLists& tl, int width, int height, double pad, RayFn ray, const Eigen::Vector3d& apex,
                 const Eigen::Vector3d& axis)
  {
    tl.nx = (width + kTile - 1) / kTile;
    tl.ny = (height + kTile - 1) / kTile;
    tl.cnx = (tl.nx + kCoarse - 1) / kCoarse;
    tl.cny = (tl.ny + kCoarse - 1) / kCoarse;
    auto frustum = [&](int x0, int y0, int x1, int y1) {  // pixel range, inclusive
      const double a = x0 - 0.5 - pad, b = x1 + 0.5 + pad, c = y0 - 0.5 - pad, d = y1 + 0.5 + pad;
      return makeFrustum(apex, axis, ray(a, c), ray(b, c), ray(a, d), ray(b, d));
    };
    for (int ty = 0; ty < tl.ny; ++ty)
      for (int tx = 0; tx < tl.nx; ++tx)
        tl.fine.push_back(frustum(tx * kTile, ty * kTile, std::min(width, (tx + 1) * kTile) - 1,
                                  std::min(height, (ty + 1) * kTile) - 1));
    const int ck = kTile * kCoarse;
    for (int ty = 0; ty < tl.cny; ++ty)
      for (int tx = 0; tx < tl.cnx; ++tx)
        tl.coarse.push_back(
            frustum(tx * ck, ty * ck, std::min(width, (tx + 1) * ck) - 1, std::min(height, (ty + 1) * ck) - 1));
    tl.counts.assign(tl.fine.size(), 0);
    tl.coarse_counts.assign(tl.coarse.size(), 0);
  }

  void buildTables()
  {
    const SimSettings& s = settings;
    // Vignetting: 1 at the principal point, falling quadratically with the radius to `vignetting`
    // at the farthest image corner; the exposure folded in.
    vignette.resize(static_cast<size_t>(W) * H);
    const double cx = rig.camera.cx, cy = rig.camera.cy;
    double r2max = 0.0;
    for (double u : { -0.5, W - 0.5 })
      for (double v : { -0.5, H - 0.5 })
        r2max = std::max(r2max, (u - cx) * (u - cx) + (v - cy) * (v - cy));
    for (int v = 0; v < H; ++v)
      for (int u = 0; u < W; ++u)
      {
        const double r2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / r2max;
        vignette[static_cast<size_t>(v) * W + u] = static_cast<float>(s.exposure * (1.0 - (1.0 - s.vignetting) * r2));
      }
    // Output curve: 12-bit linear signal to 8 bits with gamma.
    lut.resize(kLutSize);
    for (int i = 0; i < kLutSize; ++i)
    {
      const double x = static_cast<double>(i) / (kLutSize - 1);
      lut[static_cast<size_t>(i)] =
          static_cast<int32_t>(std::min(255.0, std::floor(255.0 * std::pow(x, 1.0 / s.gamma) + 0.5)));
    }
    // Tileable fractal value noise: octaves of smoothstep-interpolated lattice noise, periods 16, 8,
    // 4 texels (a `scale` is 16 texels).
    texture.assign(static_cast<size_t>(kTextureSize) * kTextureSize, 0.f);
    float amplitude = 1.f;
    for (int period = 16; period >= 4; period /= 2)
    {
      const int cells = kTextureSize / period;
      auto lattice = [&](int i, int j)
      {
        const uint32_t h = hash32(static_cast<uint32_t>(((i % cells) * 7919 + (j % cells)) * 31 + period));
        return static_cast<float>(h >> 8) / 16777216.f;
      };
      for (int y = 0; y < kTextureSize; ++y)
        for (int x = 0; x < kTextureSize; ++x)
        {
          const int cx0 = x / period, cy0 = y / period;
          float fx = static_cast<float>(x % period) / period, fy = static_cast<float>(y % period) / period;
          fx = fx * fx * (3.f - 2.f * fx);
          fy = fy * fy * (3.f - 2.f * fy);
          const float a = lattice(cx0, cy0), b = lattice(cx0 + 1, cy0), c = lattice(cx0, cy0 + 1),
                      d = lattice(cx0 + 1, cy0 + 1);
          texture[static_cast<size_t>(y) * kTextureSize + x] +=
              amplitude * ((a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy);
        }
      amplitude *= 0.5f;
    }
    const auto range = std::minmax_element(texture.begin(), texture.end());
    const float lo = *range.first, hi = *range.second;
    for (float& v : texture)
      v = (v - lo) / std::max(hi - lo, 1e-6f);
  }

  void updatePattern(const cv::Mat& pattern)
  {
    if (pattern.empty() || pattern.type() != CV_8UC1 || pattern.cols != Wp || pattern.rows != Hp)
      throw std::invalid_argument("pattern: must be a CV_8UC1 image of the projector's " + std::to_string(Wp) + " x " +
                                  std::to_string(Hp) + " px, got " + std::to_string(pattern.cols) + " x " +
                                  std::to_string(pattern.rows) + " of OpenCV type " + std::to_string(pattern.type()));
    bool same = !pattern_copy.empty();
    for (int y = 0; same && y < Hp; ++y)
      same = std::memcmp(pattern.ptr<uint8_t>(y), pattern_copy.ptr<uint8_t>(y), static_cast<size_t>(Wp)) == 0;
    if (same)
      return;
    pattern.copyTo(pattern_copy);
    cv::Mat base;
    pattern.convertTo(base, CV_32F, 1.0 / 255.0);
    level_w = Wp + 2 * kPatternPad;
    level_h = Hp + 2 * kPatternPad;
    level_size = level_w * level_h;
    // A spare zero level after the last one: trilinear reads stay inside the buffer.
    pattern_levels.assign(static_cast<size_t>(level_size) * (kPatternLevels + 1), 0u);
    cv::Mat level(level_h, level_w, CV_32F);
    for (int k = 0; k < kPatternLevels; ++k)
    {
      cv::Mat blurred;
      if (k == 0)
        blurred = base;
      else
      {
        const double s = kPatternSigma1 * std::pow(std::sqrt(2.0), k - 1);
        cv::GaussianBlur(base, blurred, cv::Size(0, 0), s, s, cv::BORDER_CONSTANT);
      }
      level.setTo(0.f);
      blurred.copyTo(level(cv::Rect(kPatternPad, kPatternPad, Wp, Hp)));
      uint32_t* packed = pattern_levels.data() + static_cast<size_t>(k) * level_size;
      for (int y = 0; y < level_h; ++y)
        for (int x = 0; x < level_w; ++x)
        {
          auto q = [&](int xx)
          {
            const float v = xx < level_w ? level.at<float>(y, xx) : 0.f;
            return static_cast<uint32_t>(std::min(std::max(v, 0.f), 1.f) * 65535.f + 0.5f);
          };
          packed[static_cast<size_t>(y) * level_w + x] = q(x) | (q(x + 1) << 16);
        }
    }
  }

  void prepareScene(const Scene& scene, const Eigen::Isometry3d& camera_in_world)
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
  static bool inside(const RenderObject& o, const Frustum& f)
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
  static float nearDepth(const RenderObject& o, const Frustum& f)
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

  void cull(TileLists& tl)
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

  uint32_t nextMark()
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
  void trace(Lanes& b, const float* dx, const float* dy, int n, const Segment* segments, int n_segments)
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

    sim::projectLanes(kp, dx, dy, b.t, b.obj, b.nx, b.ny, b.nz, n, b.u, b.v, b.e, b.level, b.sx, b.sy, b.sz, b.lit,
                      b.csig, b.pz);

    // Shadow rays from the projector centre to the lit points, against the objects of the
    // projector tiles those points fall in.
    // The projector tiles are those overlapping the bounding box of the lanes' projector pixels.
    const uint32_t pm = nextMark();
    shadow_list.clear();
    float box[5];
    const bool any_lit = sim::litBounds(b.u, b.v, b.lit, b.pz, n, box);
    if (any_lit && settings.shadows)  // with shadows off no occluder is gathered
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
            if (obj_mark[pl[j]] != pm)
            {
              obj_mark[pl[j]] = pm;
              shadow_list.push_back(pl[j]);
            }
        }
    }
    if (any_lit && !shadow_list.empty())
    {
      for (int i = 0; i < n; ++i)
        b.tsh[i] = b.lit[i] ? kShadowTMax : -1.f;
      for (uint16_t k : shadow_list)
        sim::intersectLanes(objects[k].proj, b.sx, b.sy, b.sz, n, kShadowTMin, b.tsh, b.shobj, b.shpart, b.obj);
      sim::shadowLanes(b.tsh, kShadowTMax, n, b.lit, b.u, b.v);
    }

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

  void castPrimary(RenderOutput& out)
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
        trace(b, tile_dx.data() + static_cast<size_t>(tile) * kLanes,
              tile_dy.data() + static_cast<size_t>(tile) * kLanes, npad, &whole, 1);
        const size_t p0 = static_cast<size_t>(y0) * W + x0;
        max_sigma = std::max(max_sigma, sim::storeTile(th, tw, b.radiance, b.t, b.obj, b.part, b.lit, b.parity, b.u,
                                                       b.v, b.csig, radiance + p0, out.depth.ptr<float>(y0) + x0,
                                                       out.projector_coords.ptr<float>(y0) + 2 * x0, keys.data() + p0,
                                                       W, static_cast<int>(out.depth.step1()),
                                                       static_cast<int>(out.projector_coords.step1())));
      }
  }

  // Pixels on edges (object, face, shadow, texture square) get more rays: the centre sample plus
  // aa_offsets, averaged. The rays of the edge pixels of consecutive tiles fill batches of lanes;
  // each tile's rays form a segment traced against that tile's objects.
  void antialias()
  {
    if (aa_offsets.empty())
      return;
    sim::markEdges(keys.data(), W, H, edge.data());
    edge_pixels.clear();
    Lanes& b = *lanes;
    float* radiance = levels.data();
    const int extra = static_cast<int>(aa_offsets.size());
    const float weight = 1.f / static_cast<float>(extra + (aa_with_centre ? 1 : 0));
    int n = 0;
    segments.clear();
    auto flush = [&]()
    {
      if (n == 0)
        return;
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
    };
    for (int ty = 0; ty < cam_tiles.ny; ++ty)
      for (int tx = 0; tx < cam_tiles.nx; ++tx)
      {
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
              flush();
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
              b.dx[n] = a.w[0] * ray_x[g] + a.w[1] * ray_x[g + 1] + a.w[2] * ray_x[g + grid_w] +
                        a.w[3] * ray_x[g + grid_w + 1];
              b.dy[n] = a.w[0] * ray_y[g] + a.w[1] * ray_y[g + 1] + a.w[2] * ray_y[g + grid_w] +
                        a.w[3] * ray_y[g + grid_w + 1];
              b.pixel[n] = static_cast<int>(p);
              ++n;
            }
            segments.back().end = n;
          }
        }
      }
    flush();
  }

  int cameraLevelsNeeded() const
  {
    int n = 1;
    while (n < kCameraLevels && kCameraTopSigma[n - 1] < max_sigma)
      ++n;
    return n;
  }

  float* level(int k) { return levels.data() + static_cast<size_t>(k) * W * H; }

  // Camera blur levels: 1 and 2 at full resolution, 3 (2 px) at half, 4 (4 px) and the glare halo
  // at quarter resolution, their rows upsampled horizontally (the sensor interpolates vertically).
  void blurCamera(int n_levels, bool need_glare)
  {
    if (need_glare)
      n_levels = kCameraLevels;
    if (n_levels > 1)
      sim::blurImage(level(0), level(1), W, H, k1.w.data(), k1.radius, tmp.data(), row.data());
    if (n_levels > 2)
      sim::blurImage(level(1), level(2), W, H, k2.w.data(), k2.radius, tmp.data(), row.data());
    if (n_levels > 3)
    {
      sim::downsample2(level(2), W, H, half_in.data(), hw, hh);
      sim::blurImage(half_in.data(), half_blur.data(), hw, hh, k3.w.data(), k3.radius, tmp.data(), row.data());
      sim::upsampleRows2(half_blur.data(), hw, hh, rows_half.data(), row_stride, row.data());
    }
    if (n_levels > 4)
    {
      sim::downsample2(half_blur.data(), hw, hh, quarter_in.data(), qw, qh);
      sim::blurImage(quarter_in.data(), quarter_blur.data(), qw, qh, k4.w.data(), k4.radius, tmp.data(), row.data());
      sim::upsampleRows4(quarter_blur.data(), qw, qh, rows_quarter.data(), row_stride, row.data());
    }
    if (need_glare)
    {
      sim::blurImage(quarter_in.data(), quarter_halo.data(), qw, qh, kglare.w.data(), kglare.radius, tmp.data(),
                     row.data());
      sim::upsampleRows4(quarter_halo.data(), qw, qh, rows_halo.data(), row_stride, row.data());
    }
  }

  void sensor(uint64_t seed, const cv::Mat& depth, cv::Mat& image)
  {
    const int n_levels = cameraLevelsNeeded();
    const bool glare = settings.glare > 0.0;
    blurCamera(n_levels, glare);
    sim::KSensor s;
    for (int k = 0; k < 3; ++k)
      s.levels[k] = level(k);
    s.n_levels = n_levels;
    s.glare = glare ? static_cast<float>(settings.glare) : 0.f;
    s.vignette = vignette.data();
    s.lut = settings.gamma == 1.0 ? nullptr : lut.data();
    s.cam_base2 = kp.cam_base2;
    s.cam_defocus_k = kp.cam_defocus_k;
    s.cam_inv_focus = kp.cam_inv_focus;
    s.noise = settings.noise;
    s.inv_full_well = static_cast<float>(1.0 / settings.full_well);
    const float read = static_cast<float>(settings.read_noise / 255.0);
    s.read2 = read * read;
    const uint64_t k = mix64(seed);
    s.key_a = static_cast<uint32_t>(k);
    s.key_b = static_cast<uint32_t>(k >> 32);
    // Rows not computed this frame have weight 0; any valid row will do.
    const float* fallback = level(0);
    for (int v = 0; v < H; ++v)
    {
      sim::KSensorRow r;
      const size_t yh = static_cast<size_t>(up_half.y0[static_cast<size_t>(v)]);
      const size_t yq = static_cast<size_t>(up_quarter.y0[static_cast<size_t>(v)]);
      const size_t yh1 = std::min(yh + 1, static_cast<size_t>(hh - 1)),
                   yq1 = std::min(yq + 1, static_cast<size_t>(qh - 1));
      const bool has3 = n_levels > 3, has4 = n_levels > 4;
      r.l3[0] = has3 ? rows_half.data() + yh * row_stride : fallback;
      r.l3[1] = has3 ? rows_half.data() + yh1 * row_stride : fallback;
      r.f3 = up_half.fy[static_cast<size_t>(v)];
      r.l4[0] = has4 ? rows_quarter.data() + yq * row_stride : fallback;
      r.l4[1] = has4 ? rows_quarter.data() + yq1 * row_stride : fallback;
      r.f4 = up_quarter.fy[static_cast<size_t>(v)];
      r.halo[0] = glare ? rows_halo.data() + yq * row_stride : fallback;
      r.halo[1] = glare ? rows_halo.data() + yq1 * row_stride : fallback;
      r.fh = r.f4;
      sim::sensorRow(s, r, depth.ptr<float>(v), v * W, W, row.data(), image.ptr<uint8_t>(v));
    }
  }
};

Renderer::Renderer(const sl_projector::Rig& rig, const SimSettings& settings) : impl_(new Impl(rig, settings)) {}

Renderer::~Renderer() = default;

const sl_projector::Rig& Renderer::rig() const
{
  return impl_->rig;
}

const SimSettings& Renderer::settings() const
{
  return impl_->settings;
}

double Renderer::cameraBlurSigma(double depth) const
{
  const Impl& m = *impl_;
  const double defocus = m.cam_defocus_k * std::abs(1.0 / depth - 1.0 / m.settings.camera_focus_distance);
  return std::sqrt(m.settings.camera_base_blur * m.settings.camera_base_blur + defocus * defocus);
}

double Renderer::projectorBlurSigma(double distance) const
{
  const Impl& m = *impl_;
  const double defocus = m.proj_defocus_k * std::abs(1.0 / distance - 1.0 / m.settings.projector_focus_distance);
  return std::sqrt(m.settings.projector_base_blur * m.settings.projector_base_blur + defocus * defocus);
}

void Renderer::render(const Scene& scene, const cv::Mat& pattern_mono8,
                      const Eigen::Isometry3d& camera_optical_in_world, uint64_t seed, RenderOutput& out)
{
  Impl& m = *impl_;
  m.updatePattern(pattern_mono8);
  m.prepareScene(scene, camera_optical_in_world);
  m.cull(m.cam_tiles);
  m.cull(m.proj_tiles);
  out.image.create(m.H, m.W, CV_8UC1);
  out.depth.create(m.H, m.W, CV_32FC1);
  out.projector_coords.create(m.H, m.W, CV_32FC2);
  m.castPrimary(out);
  m.antialias();
  m.sensor(seed, out.depth, out.image);
}

Eigen::Isometry3d toIsometry(const sl_projector::RigidTransform& transform)
{
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = transform.rotation;
  iso.translation() = transform.translation;
  return iso;
}

Eigen::Isometry3d cameraPoseInWorld(const sl_projector::Rig& rig, const Eigen::Isometry3d& platform_edge_in_world)
{
  return platform_edge_in_world * toIsometry(rig.mount.cameraOpticalInParent());
}

}  // namespace sl_sim
