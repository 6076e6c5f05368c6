#pragma once
// Internal: the renderer's data-parallel kernels. Each works on "lanes" (one ray each, structure of
// arrays, up to kLanes) with branch-free loops that the compiler vectorises; on x86-64 each kernel
// is also built for x86-64-v3 (AVX2, FMA) and chosen at run time; the kernels that need gathers
// (pattern and noise lookups) have AVX2 versions written out, chosen at run time as well.
// Implemented by stage in lanes_intersect.cpp, lanes_surface.cpp, lanes_projector.cpp and
// lanes_image.cpp (shared helpers: lanes_common.h).
#include <cstdint>

namespace sl_sim
{
namespace sim
{

constexpr int kLanes = 256;  // a 16 x 16 pixel tile, or a batch of anti-aliasing rays

/// An object for the intersection kernels: frame axes, ray origin in local coordinates, half sizes.
struct KObject
{
  int type = 0;      ///< 0 plane, 1 box, 2 cylinder (as ObjectType)
  int id = 0;        ///< object index, written to the lanes it is the nearest hit of
  int infinite = 0;  ///< infinite plane
  float a[9] = {};   ///< a[3 * c + r]: component r of local axis c, in the frame
  float o[3] = {};   ///< the rays' common origin in local coordinates
  float h[3] = {};   ///< half sizes (plane: x, y; box: x, y, z; cylinder: r, r, half height)
};

/**
 * Nearest-hit update: where origin + t' d meets the object with tmin < t' < t[i] and self[i] != id,
 * sets t[i] = t', obj[i] = id and part[i] (box face 0..5, cylinder 0 side, 1 top, 2 bottom).
 * Returns true if any lane was updated.
 */
bool intersectLanes(const KObject& o, const float* dx, const float* dy, const float* dz, int n, float tmin, float* t,
                    int32_t* obj, int32_t* part, const int32_t* self);

/// The largest of x[0..n-1], all >= 0 (+inf allowed).
float maxLanes(const float* x, int n);

/// Surface of one object at the lanes it is the nearest hit of (rays (dx, dy, 1) from the camera).
struct KSurface
{
  KObject g;                                                              ///< geometry, origin = the camera
  int texture = 0;                                                        ///< TextureType as int
  float albedo = 0.f;                                                     ///< base albedo
  float inv_scale = 1.f;                                                  ///< 1 / texture scale
  float contrast = 0.f;                                                   ///< texture contrast
  float off_u = 0.f, off_v = 0.f;                                         ///< noise texture offsets, texels
  int cols = 0, rows = 0;                                                 ///< checkerboard squares
  float inv_square = 1.f, half_w = 0.f, half_h = 0.f, dark_albedo = 0.f;  ///< checkerboard
};

/// Camera-facing unit normal, albedo and texture parity (0/1) at the lanes where obj[i] == s.g.id;
/// for a noise texture also the texel coordinates (tu, tv) for noiseLanes().
void surfaceLanes(const KSurface& s, const float* dx, const float* dy, const float* t, const int32_t* obj,
                  const int32_t* part, int n, float* nx, float* ny, float* nz, float* albedo, int32_t* parity,
                  float* tu, float* tv);

/// Multiplies the albedo of the lanes where obj[i] == id by 1 - contrast * noise(tu, tv), noise from
/// the tileable 256 x 256 texture (bilinear, wrapping).
void noiseLanes(int id, float contrast, const float* noise_texture, const int32_t* obj, const float* tu,
                const float* tv, int n, float* albedo);

/// The projector and the optics, for projectLanes().
struct KProjector
{
  float r[9] = {};   ///< camera -> projector rotation, row-major
  float tr[3] = {};  ///< camera -> projector translation
  float c[3] = {};   ///< projector centre in the camera frame
  float fx = 0, fy = 0, cx = 0, cy = 0;
  float k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  float umax = 0, vmax = 0;                                           ///< frame size - 0.5
  float frame_cx = 0, frame_cy = 0, inv_half_diag2 = 0, falloff = 0;  ///< lens falloff: 1 - falloff * r^2
  float power_focus2 = 0;                                             ///< projector_power * focus distance^2
  float falloff_weight = 1;  ///< 1: irradiance falls with distance^2 and the incidence cosine; 0: it does not
  float flat_power = 0;      ///< irradiance added when it does not fall (projector_power), else 0
  float defocus_k = 0, inv_focus = 0, base2 = 0, footprint_k = 0;
  float cam_defocus_k = 0, cam_inv_focus = 0, cam_base2 = 0;
  float sigma1 = 0.3f;  ///< sigma of pattern level 1 (level 0 is sharp)
  float max_level = 0;  ///< last pattern level
};

/**
 * Projector side of each lane's hit point: projector pixel (u, v), irradiance e (0 where unlit),
 * pattern level (fractional), the segment s = P - projector centre (for shadow rays), lit (hit,
 * facing the projector, inside its frame), the camera blur sigma (px) at the lane's depth and the
 * point's depth along the projector's axis.
 */
void projectLanes(const KProjector& p, const float* dx, const float* dy, const float* t, const int32_t* obj,
                  const float* nx, const float* ny, const float* nz, int n, float* u, float* v, float* e, float* level,
                  float* sx, float* sy, float* sz, int32_t* lit, float* cam_sigma, float* proj_depth);

/// Bounds of the lit lanes: box = {min u, max u, min v, max v, max proj_depth}; false if none is lit.
bool litBounds(const float* u, const float* v, const int32_t* lit, const float* proj_depth, int n, float* box);

/// Lanes whose shadow ray stopped before t_max (tsh < t_max) become unlit, with NaN (u, v).
void shadowLanes(const float* tsh, float t_max, int n, int32_t* lit, float* u, float* v);

/// Trilinear pattern lookup at (u, v, level) for the lit lanes (0 elsewhere). Levels are stored one
/// after the other, `level_size` entries apart (plus a spare zero level), rows `stride` entries,
/// with a zero border of `pad`; each entry packs the values (0..65535) at x (low 16 bits) and x + 1.
void patternLanes(const uint32_t* levels, int level_size, int stride, int pad, const float* u, const float* v,
                  const float* level, const int32_t* lit, int n, float* value);

/// Radiance of the lanes: albedo (ambient + e (black + (1 - black) pattern)); direct = the
/// projector term e (black + (1 - black) pattern) (0 where unlit).
void radianceLanes(float ambient, float black, const float* albedo, const float* e, const float* pattern,
                   const int32_t* lit, int n, float* direct, float* radiance);

/// Adds a normalised Blinn-Phong lobe (weight ks_norm, exponent shininess) lit by the projector to
/// the lanes where obj[i] == id.
void specularLanes(int id, float ks_norm, float shininess, const float* dx, const float* dy, const float* sx,
                   const float* sy, const float* sz, const float* nx, const float* ny, const float* nz,
                   const int32_t* obj, const float* direct, int n, float* radiance);

/// Stores `rows` x `cols` lanes (row-major) of a traced tile: radiance, depth (t, NaN where nothing
/// was hit), projector coordinates (u, v interleaved), and the anti-aliasing key (object + 1 in bits
/// 0..10, part 11..13, lit 14, texture parity 15; 0 where nothing was hit). Output pointers are at the
/// tile's top-left pixel; strides in elements. Returns the largest cam_sigma of the lanes.
float storeTile(int rows, int cols, const float* radiance, const float* t, const int32_t* obj, const int32_t* part,
                const int32_t* lit, const int32_t* parity, const float* u, const float* v, const float* cam_sigma,
                float* radiance_out, float* depth_out, float* coords_out, uint16_t* keys_out, int stride,
                int depth_stride, int coords_stride);

/// edge[p] = 1 where the key of pixel p differs from a 4-neighbour's, else 0.
void markEdges(const uint16_t* keys, int w, int h, uint8_t* edge);

/// Separable Gaussian blur (replicated border) of a w x h float image with 2 r + 1 taps (r <= 31);
/// tmp: w * h, row: w + 2 r.
void blurImage(const float* src, float* dst, int w, int h, const float* kernel, int radius, float* tmp, float* row);

/// 2 x 2 average (odd sizes replicate the last row/column).
void downsample2(const float* src, int w, int h, float* dst, int dw, int dh);

/// Horizontal upsampling of each row of a (sw x sh) image by 2 (linear, pixel centres aligned,
/// edges replicated) into rows of dst_stride >= 2 sw floats; `pad` is scratch of sw + 2 floats.
void upsampleRows2(const float* src, int sw, int sh, float* dst, int dst_stride, float* pad);

/// The same by 4 (dst_stride >= 4 sw).
void upsampleRows4(const float* src, int sw, int sh, float* dst, int dst_stride, float* pad);

/// The sensor on one row: blend of the camera blur levels by the depth's blur sigma, glare,
/// vignetting (with the exposure), shot and read noise (an approximately Gaussian sample from a
/// seeded hash of the pixel index), then 12-bit quantisation and the output curve (lut, or linear
/// when lut is null).
struct KSensor
{
  const float* levels[3];  ///< full-resolution blur levels, sigma 0, 0.5, 1 px (whole images)
  int n_levels;            ///< levels available (1..5): 4 adds sigma 2 px, 5 sigma 4 px (rows below)
  float glare;             ///< fraction of light in the halo (0: none)
  const float* vignette;   ///< per pixel, exposure included
  const int32_t* lut;      ///< 12-bit -> 8-bit output curve (4096 entries), null for linear
  float cam_base2, cam_defocus_k, cam_inv_focus;  ///< camera blur from depth (see KProjector)
  bool noise;
  float inv_full_well, read2;
  uint32_t key_a, key_b;  ///< frame keys from the seed
};
/// The low-resolution levels on one row: two upsampled source rows and the weight of the second.
struct KSensorRow
{
  const float* l3[2];
  float f3;
  const float* l4[2];
  float f4;
  const float* halo[2];
  float fh;
};
void sensorRow(const KSensor& s, const KSensorRow& r, const float* depth, int first_index, int n, float* scratch,
               uint8_t* out);

}  // namespace sim
}  // namespace sl_sim
