#pragma once
/// @file blob_detector.h
/// @brief Local thresholding and 8-connected run-based labelling in one pass (ROS-free).

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_decoder/blob.h"
#include "sl_decoder/decoder_config.h"

namespace sl_decoder
{
namespace local_threshold
{
struct RowConstants;
struct RowInput;
}  // namespace local_threshold

/**
 * @brief Finds candidate primitives: pixels brighter than their local mean by an offset, grouped
 * into 8-connected components, filtered for speckles, bands and oversized patches.
 *
 * Thresholding and run extraction happen in one pass over the image, with the local mean from
 * column sums slid down the image; components are formed by union-find over runs. A run keeps only
 * its peak weight; centroids() weighs the pixels of the few blobs that need it again, from the
 * image. All buffers are reused across calls: after the first images of a given size and content,
 * detect() does not allocate.
 *
 * Near the camera, defocus and overexposure fill the gaps between primitives, so whole rows of them
 * come out as one component. With DecoderConfig::split_merged, a component too large for a
 * primitive is therefore re-thresholded, over its own pixels only, at rising fractions of its grey
 * range (like the stable regions of MSER): the bridges between primitives are dimmer than their
 * cores, so at some level the parts that pass the filters appear. Such blobs carry the level in
 * Blob::level. Each level only looks at the pixels of the parts the previous level kept (a part
 * that is all of its region above the threshold is read through the region's pixels), so the work
 * is at most kLastLevel times the component's area, whatever the image.
 */
class BlobDetector
{
public:
  /// @brief Uses @p config (validated by the caller).
  explicit BlobDetector(const DecoderConfig& config = DecoderConfig());
  // Defined where local_threshold::RowConstants is complete.
  ~BlobDetector();
  BlobDetector(const BlobDetector&);
  BlobDetector(BlobDetector&&) noexcept;
  BlobDetector& operator=(const BlobDetector&);
  BlobDetector& operator=(BlobDetector&&) noexcept;

  /**
   * @brief Detects blobs in a CV_8UC1 image: detectBoxes(), then centroids().
   * @param image mono8 image.
   * @param[out] blobs cleared and filled (capacity reused).
   */
  void detect(const cv::Mat& image, std::vector<Blob>& blobs);

  /**
   * @brief Detects blobs as detect() does, but leaves the centroid (u, v) of the blobs that are
   * whole components NaN: centroids() sets the ones still NaN later.
   *
   * The decoder replaces the centroid of every identified blob (ShapeClassifier::refineCentroid),
   * so it only asks for the others' (and for those whose refinement found no light). Blobs split
   * from oversized components and saturated bands get their centroid here.
   */
  void detectBoxes(const cv::Mat& image, std::vector<Blob>& blobs);

  /**
   * @brief Sets u, v of the blobs of the last detectBoxes() whose u is still NaN: the centroid of
   * their pixels weighted by value minus local mean, the same floats as detect() gives.
   *
   * The weights are formed again from the image of that call (kept by reference: it must not have
   * changed), over each such blob's box only.
   * @param blobs the vector detectBoxes() filled (its first blobs unmoved; u, v may be set).
   */
  void centroids(std::vector<Blob>& blobs);

  /**
   * @brief The size of one primitive's box in the image (from the rig at the nominal depth), px.
   * Components wider than 1.6 times it are split as merged; split parts may be at most 1.4 times
   * it. @p pitch is the horizontal distance of neighbouring primitives: a row of them merged by
   * saturated bridges is cut at that pitch. 0 (the default) disables these tests. @p slope is the
   * tilt of the pattern's rows in the image (dy / dx; a rolled projector or camera): a merged row
   * is followed along it.
   */
  void setPrimitiveSize(double width, double height, double pitch, double slope = 0.0)
  {
    primitive_w_ = width;
    primitive_h_ = height;
    pitch_ = pitch;
    slope_ = slope;
  }

  /// @brief Blob::level of primitives read from the outline of a saturated row: their shape and
  /// centroid are set by the detector (the box's centre; the decoder adds the shape's offset).
  static constexpr int kBandLevel = 7;

  /// @brief Instruction sets of the local threshold. All give bit-identical blobs.
  enum class Simd
  {
    Portable,  ///< plain C++
    Sse2,      ///< x86-64 baseline
    Avx2       ///< where the CPU has it (checked at run time)
  };

  /// @brief Uses @p simd, or the widest set below it that this CPU has; returns the set in use.
  /// The default is the widest the CPU has; other choices are for tests and benchmarks.
  Simd useSimd(Simd simd);

  /// @brief Number of components found before filtering in the last call.
  int componentCount() const { return static_cast<int>(boxes_.size()); }

  /// @brief Pixels of the parts re-thresholded while splitting oversized components in the last
  /// call: at most kLastLevel (5) times their area, so never more than 5 times the image.
  long splitPixels() const { return split_pixels_; }

private:
  struct Run
  {
    Run() {}            // uninitialised: runs_ grows by a row's worst case before its runs are written
    int32_t y, x0, x1;  // [x0, x1)
    int32_t parent;     // union-find over runs
    float peak;         // max weight
  };

  /// Pixels [x0, x1) of row y.
  struct Span
  {
    Span() {}  // uninitialised: spans_ grows by the regions' run counts before they are written
    Span(int32_t row, int32_t first, int32_t end) : y(row), x0(first), x1(end) {}
    int32_t y, x0, x1;
  };

  /// A component being split: its box (and level) and its pixels, spans_[begin, end) in row order.
  /// A part that is all of its region above its threshold keeps the region's spans: then they hold
  /// more pixels (span_area) than it has (box.area), all at or below that threshold.
  struct Region
  {
    Blob box;
    int32_t begin, end;
    int32_t span_area;
  };

  /// A component of the row pass: its box, pixel count, peak weight and its first and last run.
  struct Box
  {
    Box() {}  // uninitialised: boxes_ grows by the worst case before they are formed
    int32_t x0, x1, y0, y1, area;
    float peak;
    int32_t first, last;
  };

  struct Acc
  {
    float sw, swx, swy;
  };

  // Inline (defined in blob_detector.cpp, the only user): called per run, a call through the shared
  // library's PLT cost more than the work.
  inline int find(int i);
  inline void unite(int a, int b);
  /// Thresholds every row, extracts its runs (with their peaks) and links them to the row above.
  void thresholdAndLink(const cv::Mat& image);
  /// The same with column and prefix sums of type @p T (int32_t, or uint16_t modulo 2^16).
  template <class T>
  void thresholdAndLink(const cv::Mat& image, std::vector<T>& col_sums, std::vector<T>& prefix);
  /// The threshold's constants of rows like @p row (formed at their first use in an image).
  const local_threshold::RowConstants& constantsOf(const local_threshold::RowInput& row);
  /// Appends the runs of row @p y from the bit mask bits_, with their peak weight (weight_).
  void extractRuns(int y, int w);
  /// Writes the run [x0, x1) of row @p y (its own root) at @p out (runs_ starts at @p begin).
  inline Run* putRun(Run* out, const Run* begin, int y, int x0, int x1) const;
  /// An integral image in box_sums_: its first column and row in the image, and its row stride.
  struct Integral
  {
    int x0, y0, stride;
  };
  /// Integrates image_ over the windows of the pixels of component @p c (its box grown by them).
  Integral integrateAround(const Box& c);
  /// Adds the pixels of @p run, weighted by value minus local mean (the row pass's floats), to @p acc.
  void accumulate(const Run& run, const Integral& sums, Acc& acc) const;
  /// Unites the runs [cur_begin, cur_end) of a row with the 8-connected ones of the row above.
  void linkRows(int prev_begin, int prev_end, int cur_begin, int cur_end);
  /// Labels the linked runs_ (component_of_) and forms the components' boxes_.
  void formComponents();
  /// Sets @p b to the box of a component whose first run is @p run (index @p first), still empty.
  static inline void startBox(Box& b, const Run& run, int32_t first);
  /// True when a finished blob passes the size, aspect and fill filters.
  bool primitiveSized(const Blob& b) const;
  /// True when a blob is wider than two merged primitives would need to be.
  bool merged(const Blob& b) const { return primitive_w_ > 0.0 && b.width() > 1.6 * primitive_w_; }
  /// Copies the runs of the components in oversized_ (oversized_component_) into spans_.
  void collectSpans();
  /// Re-thresholds the pixels of an oversized component; parts that pass the filters join @p blobs.
  void splitOversized(const cv::Mat& image, const Region& component, std::vector<Blob>& blobs);
  /// Cuts a saturated row of merged primitives into pieces of the pattern's pitch.
  /// False (and nothing added) when the part is not a few primitives wide.
  bool cutByPitch(const cv::Mat& image, const Blob& part, int threshold, std::vector<Blob>& blobs);
  /// Places and identifies the primitives of a saturated row from its outline at grey level @p t.
  void cellsOfBand(const cv::Mat& image, const Blob& band, int t, std::vector<Blob>& blobs);
  /// Sets cos_, sin_ to the cosine and sine of @p omega x for the columns x of an image @p cols wide.
  void formWaveTable(double omega, int cols);
  /// Centroid (weights above @p threshold), contrast and area (pixels above) of @p b's box; false if none.
  bool weighAbove(const cv::Mat& image, Blob& b, int threshold) const;
  /// The same over the pixels of @p part only (neighbours' light in its box does not pull it).
  bool weighAbove(const cv::Mat& image, Region& part, int threshold) const;
  /// Sets @p b's centroid (weight sums @p sw, @p swx, @p swy) and contrast (@p peak); false if @p sw is 0.
  static bool setWeighted(int64_t sw, int64_t swx, int64_t swy, int peak, Blob& b);
  /// Labels the pixels of @p region above @p threshold (8-connected); the parts (box, area and
  /// their pixels, appended to spans_; a single part keeps the region's spans) go to parts_.
  void labelAbove(const cv::Mat& image, const Region& region, int threshold);
  /// Where labelAbove() writes the next run, and the runs of the row above it may touch.
  struct LinkCursor
  {
    Run* out;
    const Run *prev, *prev_end;  // the row above: from the first run the next run may touch
    Run* row_begin;              // the current row's first run
    int y;                       // the current row
  };
  /// Moves @p c on to row @p y.
  inline void nextRow(LinkCursor& c, int y) const;
  /// Writes the run [x0, x1) of the current row at @p c with a label: that of the 8-connected runs
  /// of the row above, united in labels_, or a new one; the label's box grows by it.
  inline void linkRun(LinkCursor& c, int x0, int x1);
  /// The root of label @p l in labels_ (path halving).
  inline int findLabel(int l);
  /// Forms parts_ from the labelled runs_ and appends their pixels to spans_ (a single part keeps
  /// the spans of @p region).
  void groupRunsIntoParts(const Region& region);
  /// Appends the runs of each region (its index in @p regions: part_of_label_ of the run's label;
  /// each region's end: its run count) to spans_ and sets the regions' [begin, end).
  void appendSpans(std::vector<Region>& regions);

  DecoderConfig config_;
  Simd simd_;
  static constexpr int kRowBlock = 4;                         // rows whose prefix sums are formed side by side
  std::vector<int32_t> col_sums_;                             // column sums over the current row's window
  std::vector<int32_t> prefix_;                               // prefix sums of the column sums: kRowBlock rows
  std::vector<uint16_t> col_sums16_, prefix16_;               // the same modulo 2^16, for narrow windows
  std::vector<uint8_t> zero_row_;                             // added or dropped where a window meets the top or bottom
  std::vector<uint64_t> bits_;                                // foreground flags of the current row, one bit per pixel
  std::vector<float> weight_;                                 // value minus local mean of the current row's pixels
  std::vector<local_threshold::RowConstants> row_constants_;  // per window row count (lazily each image)
  std::vector<uint8_t> row_constants_set_;                    // per window row count: formed this image
  std::vector<Run> runs_;
  std::vector<int32_t> labels_;          // union-find over the labels of labelAbove()
  std::vector<int32_t> part_of_label_;   // per label: its part
  std::vector<Box> label_boxes_;         // per label: box, area, run count (last) of its runs
  std::vector<Run> component_runs_;      // the image's runs (runs_ is then the splitting's scratch)
  cv::Mat image_;                        // the image of the last detectBoxes(), for centroids()
  std::vector<int32_t> box_sums_;        // integral image around one blob (integrateAround())
  std::vector<Box> boxes_;               // per component of detectBoxes()
  std::vector<int32_t> component_of_;    // per run: its component
  std::vector<int32_t> kept_component_;  // per blob of the last detectBoxes() that is a whole component
  long split_pixels_ = 0;
  double primitive_w_ = 0.0, primitive_h_ = 0.0, pitch_ = 0.0, slope_ = 0.0;
  static constexpr int kLastLevel = 5;           // raised thresholds tried before cutting by the pitch
  static constexpr float kBandMinMargin = 0.3f;  // px between the lopsided and the straight edge
  std::vector<float> top_, bottom_;              // outline of a saturated band per column, px
  std::vector<double> phase_re_, phase_im_;      // prefix sums of its height times cos, sin
  std::vector<double> cos_, sin_;                // cos, sin of the pitch's phase per column (formWaveTable())
  double wave_omega_ = 0.0;                      // the angular frequency they were formed for
  // Splitting of oversized components (buffers reused).
  std::vector<Region> oversized_, pending_, parts_;
  std::vector<Span> spans_;                   // pixels of the regions above
  std::vector<int32_t> oversized_component_;  // per region of oversized_: its component
  std::vector<int32_t> region_of_component_;  // per component: its region in oversized_, or -1
};

}  // namespace sl_decoder
