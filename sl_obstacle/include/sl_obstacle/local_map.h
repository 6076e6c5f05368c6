/// @file local_map.h
/// @brief The rolling 2.5D local map in odom: log-odds height slices per cell, decay to unknown.
///
/// See doc/world_model.md, section 2. ROS-free; time is seconds on the caller's one clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sl_obstacle
{
/// Parameters of the local map. validate() names the ROS parameter of a bad value: the field name
/// with the prefix "map_" (e.g. "map_resolution must be in (0.005, 0.2] (got 0.3)").
struct MapParams
{
  /// Side of the square window centred on the robot (m). Rounded to whole cells: the window is
  /// round(size / resolution) cells wide.
  double size = 4.0;
  /// Side of a square cell (m), in (0.005, 0.2].
  double resolution = 0.02;
  /// Number of height slices splitting [z_min, z_max] into equal parts, 1..16.
  int slices = 2;
  /// Bottom of the working-volume band (m, odom z; floor_margin). Nothing below is mapped.
  double z_min = 0.015;
  /// Top of the working-volume band (m, odom z; the window height). Nothing above is mapped.
  double z_max = 0.173;
  /// Time constant of the decay toward unknown (s): log-odds * exp(-dt / decay). Must be > 0 (there
  /// is no "no decay" value; use a large one).
  double decay = 30.0;
  /// Log-odds added to a slice holding a decoded end point (occupied evidence).
  double hit = 0.85;
  /// Log-odds subtracted from a slice a free part of a ray passed through.
  double miss = 0.4;
  /// Log-odds added to a slice holding a lit (suspect) end point.
  double suspect = 0.5;
  /// Distance (m) from a ray's start within which its free part does not lower a slice that holds
  /// positive log-odds (also decayed) in a cell with hits from 3 or more (cloud, slice) pairs: next
  /// to the projector a thin leg is too near to be decoded and the floor rays that pass it by
  /// millimetres would erase it (0: off).
  double near_free = 0.3;
  /// Limit of |log-odds| of a slice.
  double clamp = 3.5;
  /// A cell is occupied when any slice's log-odds is above this (in (0, clamp)).
  double occupied_threshold = 0.6;
  /// A cell is free when every slice's log-odds is below this (in (-clamp, 0)).
  double free_threshold = -0.3;

  /// Checks the values. @throws std::invalid_argument with a message that starts with the name of
  /// the offending parameter ("map_" + field name).
  void validate() const;
};

/// What a ray says about the space it crosses (see the table in doc/world_model.md, section 1).
enum class RayKind : std::uint8_t
{
  Hit,     ///< decoded: free from start to end, occupied at the end if end.z lies in the band
  Free,    ///< floor or dark: free from start to end, nothing at the end
  Suspect  ///< lit: free from start to end, suspect at the end (see insert())
           ///< of the same batch passed through that slice
};

/// One ray in the odom frame (m): from the start (s) to the end (e).
struct MapRay
{
  float sx, sy, sz;  ///< start point (projector centre, or the checked segment's start)
  float ex, ey, ez;  ///< end point (surface point, floor hit, end of the free part)
  RayKind kind;      ///< what the end means
};

/// State of a cell (all its slices together). Unknown is never free.
enum class CellState : std::uint8_t
{
  Unknown,  ///< neither occupied nor free
  Free,     ///< every slice below free_threshold
  Occupied  ///< some slice above occupied_threshold
};

/// What the map holds for one cell, as the path checks read it.
struct CellInfo
{
  CellState state = CellState::Unknown;  ///< see CellState
  /// Some slice holds positive log-odds: occupied or suspect evidence, also decayed below
  /// occupied_threshold. An unknown cell without it was never seen, or seen free only in part (a
  /// slice no ray crossed): nothing was ever found there.
  bool evidence = false;
  /// The robot's own disc covered the cell during this run (markTrail()).
  bool trail = false;
};

/// Rolling 2.5D occupancy grid in odom (x, y in metres, z up), centred on the robot.
///
/// The window is a square of N x N cells (N = round(size / resolution)) on the global lattice of
/// cells [i * resolution, (i + 1) * resolution); each cell holds `slices` log-odds values for equal
/// height slices of [z_min, z_max] and the time of its last update. The window is a ring buffer:
/// recenter() moves it by whole cells without copying, forgetting the cells that leave. All memory
/// is allocated by the constructor (9 bytes per slice and 14 per cell: 1.3 MB for the defaults'
/// 200 x 200 x 2); nothing grows with run time. Besides the log-odds each cell holds a trail bit: the
/// robot's disc covered it (markTrail()); it is forgotten only with the cell (clear(), recenter()).
///
/// Updates of one insert() call are combined per slice (each slice changes at most once per cloud):
/// occupied wins over free, free wins over suspect. A cell decays (exp(-dt / decay)) lazily, when it
/// is updated or read. Not thread-safe: one writer, readers on the same thread (or locked).
class LocalMap
{
public:
  /// Creates an empty (all unknown) map centred on (0, 0).
  /// @throws std::invalid_argument when @p p is invalid (see MapParams::validate()).
  explicit LocalMap(const MapParams& p);

  /// Moves the window by whole cells so that (x, y) lies in its centre cell. Cells that leave the
  /// window are forgotten (unknown if the window comes back); cells that stay keep their values.
  /// Never reallocates. Non-finite input is ignored.
  void recenter(double x, double y);

  /// Inserts one cloud's rays taken at @p stamp (s). Free parts lower the log-odds of every slice
  /// they cross inside the band (3D traversal: Amanatides-Woo in x-y, z interpolated), except in a
  /// cell that holds hits, where only a ray passing near the box around those hits (grown by a
  /// quarter cell) counts, and while the cell is occupied with hits from 3 or more (cloud, slice)
  /// pairs (a surface seen again and again) only a ray through the middle of that box (shrunk by a quarter cell, but at
  /// least a twentieth of a cell either side of its centre): a ray beside a thin obstacle in the same cell, or grazing
  /// its flank from another side, says nothing about it. Nor does the free part within near_free of
  /// the ray's start lower a slice holding positive log-odds in a cell with 3 or more such pairs. Hit ends
  /// inside the band raise their slice by `hit`, from 0 where it was negative (one decoded point makes
  /// a slice occupied whatever free rays said: clouds placed a few centimetres off while the robot
  /// turns clear the cells around a thin leg), Suspect ends by `suspect`; within one batch a
  /// slice changes once: occupied beats suspect beats free where two or more Suspect rays end in
  /// the voxel, and free beats a lone Suspect end. Rays are clipped to the window; rays with a non-finite
  /// coordinate are ignored (counted in invalidRays()). No allocation.
  void insert(const std::vector<MapRay>& rays, double stamp);

  /// Marks every slice of the cells whose centre lies within @p radius of (x, y) as certainly free
  /// (log-odds -clamp): the robot's footprint, or the start area no sensor sees. To drive back along
  /// the trail, mark it with at least the swept radius (FootprintParams::sweptRadius()) plus half a
  /// cell. Non-finite input or a negative radius is ignored.
  void markFreeDisc(double x, double y, double radius, double stamp);

  /// As markFreeDisc(), except that cells where some slice holds occupied or suspect evidence
  /// (log-odds > 0) keep it: the ring just beyond the robot's body along its trail, where a thin
  /// obstacle it passed at a few millimetres may stand.
  void markFreeDiscExceptSeen(double x, double y, double radius, double stamp);

  /// Marks every slice of the cells whose centre lies within @p radius of (x, y) as certainly
  /// occupied (log-odds +clamp): a bump. Non-finite input or a negative radius is ignored.
  void markOccupiedDisc(double x, double y, double radius, double stamp);

  /// Sets the trail bit of the cells whose centre lies within @p radius of the segment from (x0, y0)
  /// to (x1, y1): the robot's disc moved along it. The log-odds are not changed. Non-finite input or
  /// a negative radius is ignored.
  void markTrail(double x0, double y0, double x1, double y1, double radius);

  /// State at @p now of the cell holding (x, y); Unknown outside the window or for NaN.
  CellState state(double x, double y, double now) const;

  /// State at @p now of the cell with global lattice index (ix, iy) (the cell
  /// [ix * resolution, (ix + 1) * resolution) x [...]); Unknown outside the window.
  CellState cellState(int ix, int iy, double now) const;

  /// State, evidence and trail bit at @p now of the cell with global lattice index (ix, iy); outside
  /// the window: Unknown, no evidence, not on the trail.
  CellInfo cellInfo(int ix, int iy, double now) const;

  /// The window as a nav_msgs/OccupancyGrid-style array, row-major from the window's origin
  /// (lower left corner, x fastest): -1 unknown, 0 free, 100 occupied with a decoded point (or a
  /// bump), 50 for a cell occupied by lit suspects alone or an unknown cell with some slice at least
  /// half-way to occupied_threshold (e.g. a single suspect). cellState() is not affected: to the
  /// decisions and the filter a suspect-occupied cell is occupied.
  /// @param data     resized to width * width (allocates only when its capacity is too small)
  /// @param origin_x x of the window's lower left corner (m, odom)
  /// @param origin_y y of the window's lower left corner (m, odom)
  /// @param width    cells per side (N); the resolution is params().resolution
  void toOccupancy(double now, std::vector<std::int8_t>& data, double& origin_x, double& origin_y, int& width) const;

  /// Forgets everything (all unknown); the window stays where it is.
  void clear();

  /// The parameters in use.
  const MapParams& params() const { return params_; }
  /// Cells per side of the window (N).
  int width() const { return n_; }
  /// Global lattice index of the cell holding coordinate @p v (m): floor(v / resolution).
  int cellIndex(double v) const;
  /// Global lattice index of the window's lower left cell (x).
  int originX() const { return ox_; }
  /// Global lattice index of the window's lower left cell (y).
  int originY() const { return oy_; }
  /// Number of rays with a non-finite coordinate ignored by the last insert() call.
  std::size_t invalidRays() const { return invalid_rays_; }

private:
  /// Ring-buffer slot of the window cell at local index (lx, ly), 0 <= lx, ly < N.
  std::size_t slot(int lx, int ly) const;
  /// Slice holding height z (z inside the band).
  int sliceOf(double z) const;
  /// Decays the cell's slices to @p stamp and records the update time.
  void decayCell(std::size_t cell, double stamp);
  /// State of a ring slot at @p now (with the lazy decay); @p suspect_out set for a near-occupied
  /// unknown cell.
  CellState slotState(std::size_t cell, double now, bool* suspect_out) const;
  /// Flags voxel @p v (slot * slices + slice) in the current batch (occupied, free or suspect).
  void touch(std::size_t v, std::uint8_t flag);
  /// Traverses one finite ray and flags its slices.
  void traverse(const MapRay& r);
  /// Flags the slices a straight piece of the ray crosses inside one cell (@p near: the piece ends
  /// within near_free of the ray's start).
  void flagCrossed(std::size_t cell, double z0, double z1, std::size_t skip_voxel, bool near);
  /// Applies the flagged updates of the current batch.
  void applyBatch(double stamp);
  /// Sets every slice of the cells in the disc to @p value (with @p keep_seen, not in cells where a
  /// slice is above 0).
  void setDisc(double x, double y, double radius, double stamp, float value, bool keep_seen = false);
  /// Grows the hit extent of the cell holding the end of Hit ray @p r (if in the window and band).
  void growExtent(const MapRay& r);
  /// True if the piece of a ray inside @p cell (from (fx, fy) in cell units from the cell's lower
  /// left corner, direction (dfx, dfy) per unit of the ray parameter, for @p dt of it) passes through
  /// the range the cell's hits ask for (see insert()), or if the cell holds no hit.
  bool passesHits(std::size_t cell, double fx, double fy, double dfx, double dfy, double dt) const;
  /// Forgets the hit extent of @p cell once no slice holds positive log-odds.
  void forgetExtentIfEmpty(std::size_t cell);

  /// Where in a cell its hits lay (1/255 of a cell from its lower left corner): the box x0..x1, y0..y1.
  struct Extent
  {
    std::uint8_t x0, y0, x1, y1;  ///< box of the hits in 1/255 of a cell from its lower left corner
    std::uint8_t hits;            ///< (cloud, slice) pairs that brought hits (saturating)
  };
  static constexpr Extent kNoExtent = { 255, 255, 0, 0, 0 };      ///< empty box: no hit
  static constexpr Extent kFullExtent = { 0, 0, 255, 255, 255 };  ///< the whole cell (a bump)
  /// Forgets the ring column (slot x) @p rx or row (slot y) @p ry.
  void clearColumn(int rx);
  void clearRow(int ry);

  MapParams params_;
  int n_ = 0;  // cells per side
  int slices_ = 1;
  double inv_res_ = 50.0;
  double slice_height_ = 0.1;
  int ox_ = 0;  // global index of the window's lower left cell
  int oy_ = 0;
  int ring_x_ = 0;  // its ring-buffer slot: ox_ mod N, oy_ mod N
  int ring_y_ = 0;
  std::vector<float> logodds_;       // slot * slices + slice
  std::vector<double> updated_;      // per slot: time of the last update (-inf: never)
  std::vector<Extent> extent_;       // per slot: box around its hits while it holds positive evidence
  std::vector<std::uint8_t> trail_;  // per slot: 1 where the robot's disc has been (markTrail())
  // Batch bookkeeping (per voxel = slot * slices + slice); flags_ is all zero between batches.
  std::vector<std::uint8_t> flags_;
  std::vector<std::uint32_t> touched_;  // voxels flagged in the current batch (sized for all)
  std::size_t touched_count_ = 0;
  double batch_stamp_ = 0.0;  // stamp of the cloud insert() is adding
  std::size_t invalid_rays_ = 0;
};
}  // namespace sl_obstacle
