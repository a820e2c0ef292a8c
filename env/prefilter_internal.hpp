#pragma once
// Internals of prefiltering (prefilter*.cpp): the working lat-long pyramid the fast methods read, the
// evaluators (direct sum, filtered importance sampling, spherical harmonics, interpolation grid,
// reference) that give the prefiltered value at one axis, the error probes, and the steps prefilter()
// takes in other files.
#include <brdfbake/env/environment.hpp>
#include <brdfbake/env/prefilter_lobe.hpp>
#include <brdfbake/maps/image.hpp>
#include <brdfbake/maps/latlong_map.hpp>
#include <brdfbake/maps/radial_table.hpp>
#include <brdfbake/maps/sh.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake::detail {

// One level of the working lat-long: an Image of LatLongMap(H) (2H x H texels, the library's
// convention, latlong_map.hpp) with tables the direct sums' inner loops read instead of calling
// trigonometric functions: cos and sin of theta at the row centres and edges, of phi at the column
// centres, and the solid angle of one texel of each row. The tables are taken from the map's own
// directions, so they follow its convention.
struct LatLongLevel {
  explicit LatLongLevel(Image levelImage);
  LatLongMap map;
  Image image;
  int height = 0, width = 0;
  std::vector<double> rowCos, rowSin, rowSolidAngle;  // at row centres; solid angle of one texel of the row
  std::vector<double> edgeCos, edgeSin;               // of theta at the H + 1 row edges
  std::vector<double> columnCos, columnSin;           // of phi at column centres

  Rgb at(int x, int y) const {
    const float* p = image.data() + image.index(x, y);
    return {p[0], p[1], p[2]};
  }
  // First of the row's RGBA floats.
  const float* row(int y) const { return image.data() + image.index(0, y); }
  // Direction of texel (x, y)'s centre.
  Vec3 direction(int x, int y) const { return *map.getDirectionFor(Vec2(x + 0.5, y + 0.5)); }
  // The library's bilinear filter (sampleBilinear): wrapped in phi, clamped in theta.
  Rgb bilinear(const Vec3& direction) const { return sampleBilinear(image, map, direction).head<3>(); }
  // The same at continuous pixel coordinates of this level.
  Rgb bilinear(const Vec2& pixel) const { return sampleBilinear(image, pixel, map.region(0), true).head<3>(); }
};

// The environment as a lat-long image with a power-of-two row count and its solid-angle mip chain
// (downsampleEnvironment, env_mips.hpp).
class LatLongPyramid {
 public:
  explicit LatLongPyramid(const Environment& environment);
  int levels() const { return static_cast<int>(levels_.size()); }
  const LatLongLevel& level(int index) const { return levels_[index]; }
  // Angular size (radians) of a texel of `index` (pi / H).
  double texelAngle(int index) const { return kPi / levels_[index].height; }
  // The coarsest level whose texels are no wider than `angle` (0 if none is).
  int levelFor(double angle) const;
  // Bilinear within and linear between the two levels about `lod` (clamped to the chain); `direction` unit.
  Rgb trilinear(const Vec3& direction, double lod) const;
  bool resampled() const { return resampled_; }
  // Solid-angle mean of |L| (RGB norm).
  double meanNorm() const { return meanNorm_; }

 private:
  std::vector<LatLongLevel> levels_;
  bool resampled_ = false;
  double meanNorm_ = 0.0;
};

// The largest azimuth offset |phi - phi_axis| (radians) of a point of the band of rows y (polar
// angles between the level's edges y and y + 1) within the cap cos(angle to the axis) >= cosCap,
// for an axis at polar angle theta_axis (cosD = cos theta_axis, sinD = sin theta_axis): pi when the
// cap may hold a whole parallel of the band (or cosCap <= -1, or the axis is at a pole), negative
// when it holds no point of the band. The direct sums visit only these columns of each row.
double capRowHalfWidth(const LatLongLevel& level, int y, double cosD, double sinD, double cosCap);

// Σ w Ω L and Σ w Ω over the texels of one pyramid level whose centres lie within the cap
// cos(angle to axis) >= cosCap, each texel split into sub x sub samples; w from `table` (on
// u = sin(theta/2)) or, if null, the exact weight.
class DirectSummer {
 public:
  DirectSummer(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int level, double cosCap, int sub,
               std::shared_ptr<const RadialTable> table);
  void sum(const Vec3& axis, Rgb& numerator, double& denominator) const;
  // mass x numerator / denominator (nearest texel if the lobe missed every sample).
  Rgb value(const Vec3& axis) const;
  // Expected texels visited per axis (cost model).
  double texelsPerAxis() const;

 private:
  const LatLongPyramid& pyramid_;
  PrefilterLobe lobe_;
  int level_, sub_;
  double cosCap_, capAngle_;
  std::shared_ptr<const RadialTable> table_;
  std::vector<double> subColumnCos_, subColumnSin_;  // sub > 1
};

// Filtered importance sampling from the pyramid.
class ImportanceSampler {
 public:
  ImportanceSampler(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int samples);
  Rgb value(const Vec3& axis) const;

 private:
  const LatLongPyramid& pyramid_;
  double mass_;
  std::vector<Vec3> local_;
  std::vector<double> lod_;  // at the equator; + 0.5 log2(1 / sin theta) elsewhere
};

// The environment projected onto SH (from a pyramid level with >= 8 rows per band) and convolved.
class ShFilter {
 public:
  ShFilter(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int order);
  Rgb value(const Vec3& axis, double* scratch) const { return expansion_.evaluate(shFrame(axis), scratch); }
  // Environment direction -> SH frame: pole on +y, azimuth phi = atan2(x, -z) as the lat-long's.
  static Vec3 shFrame(const Vec3& d) { return {-d.z(), d.x(), d.y()}; }
  int order() const { return expansion_.order; }
  int projectionLevel() const { return projectionLevel_; }

 private:
  ShExpansion expansion_;
  int projectionLevel_ = 0;
};

// A function sampled at the texel centres of a lat-long grid and interpolated bicubically
// (Catmull-Rom; wrapped in phi, continued across the poles).
class LatLongGrid {
 public:
  explicit LatLongGrid(int height)
      : map_(height), height_(height), width_(2 * height), values_(static_cast<std::size_t>(2 * height) * height) {}
  int height() const { return height_; }
  int width() const { return width_; }
  Vec3 direction(int x, int y) const;
  void set(int x, int y, const Rgb& value) { values_[static_cast<std::size_t>(y) * width_ + x] = value; }
  Rgb value(const Vec3& axis) const;

 private:
  LatLongMap map_;
  int height_, width_;
  std::vector<Rgb> values_;
};

// The direct sum (DirectSummer with sub = 1) at every point of a lat-long grid `multiple` (a power
// of two >= 1) times as fine as pyramid level `level`, by row convolutions: for one grid row and
// one source row, the weight of source column x for the grid point of column X depends only on
// x - X / multiple, so each (grid row, source row, column phase) pair computes its kernel once and
// adds it, shifted, to every point of the row (float multiply-adds over contiguous columns, which
// the compiler vectorises). Equal to DirectSummer::value at the grid's points up to float rounding.
LatLongGrid convolvedDirectGrid(const LatLongPyramid& pyramid, const PrefilterLobe& lobe, int level, double cosCap,
                                const std::shared_ptr<const RadialTable>& table, int multiple);

// The exact reference over the environment's own texels (sub-sampled where the lobe is narrow).
// With a cap (cosCap > -1) only the samples within angle acos(cosCap) of the axis count: the samples
// are kept sorted into the cells of a coarse lat-long grid, and a value visits only the cells
// that can meet the cap, so a narrow lobe costs its support, not the sphere (the error probes).
class ReferenceSummer {
 public:
  // `table` (optional): the lobe tabulated on u = sin(theta/2) (RadialTable), read instead of the
  // exact weight.
  ReferenceSummer(const Environment& environment, const PrefilterLobe& lobe, double cosCap = -1.0,
                  std::shared_ptr<const RadialTable> table = nullptr);
  Rgb value(const Vec3& axis) const;
  std::size_t samples() const { return x_.size(); }
  int subdivision() const { return sub_; }

 private:
  void sortIntoCells();
  // Adds Σ w Ω L and Σ w Ω over samples [begin, end) to out.
  void sum(const Vec3& axis, std::size_t begin, std::size_t end, double out[4]) const;
  PrefilterLobe lobe_;
  std::shared_ptr<const RadialTable> table_;
  int sub_ = 1;
  double capAngle_ = kPi;
  std::vector<double> x_, y_, z_, weight_, r_, g_, b_;  // r, g, b premultiplied by weight
  // Cells (capped only): samples of cell k are [cellStart_[k], cellStart_[k + 1]).
  LatLongMap cells_{1};
  std::vector<std::size_t> cellStart_;
  std::vector<Vec3> cellCentre_;
  double cellRadius_ = 0.0;
};

// What prefiltering one environment needs whatever the lobe, made on first use and shared by the
// lobes of one request (the levels of a gloss chain, the terms of a lobe model): the working
// pyramid and the environment's solid-angle mean |L| (the scale of prefilterErrorFloor). Not
// thread-safe: the request's own thread asks for them.
class PrefilterInput {
 public:
  explicit PrefilterInput(const Environment& environment) : environment_(environment) {}
  PrefilterInput(const PrefilterInput&) = delete;
  PrefilterInput& operator=(const PrefilterInput&) = delete;
  const Environment& environment() const { return environment_; }
  const LatLongPyramid& pyramid();
  // Σ Ω |L| / Σ Ω over the environment's own texels (|.| the RGB norm).
  double meanNorm();

 private:
  const Environment& environment_;
  std::unique_ptr<LatLongPyramid> pyramid_;
  double meanNorm_ = -1.0;
};

}  // namespace brdfbake::detail

namespace brdfbake {
struct PrefilteredMap;
struct PrefilterOptions;
struct PrefilterSummary;
}  // namespace brdfbake

namespace brdfbake::detail {

// Eye space of a sphere map -> the environment's frame (PrefilterOptions::view and up).
Mat3 eyeToEnvironment(const PrefilterOptions& options);

// |value - reference| / max(|reference|, floor), |.| the RGB norm: the metric of docs/prefilter.md.
double relativeError(const Rgb& value, const Rgb& reference, double floor);

// What the probes read: the environment (its own texels), the working pyramid, the lobe tabulated on
// u = sin(theta/2), and the lobe corrected for a box of a given angular size (direct sums' tables).
struct ProbeSources {
  const Environment& environment;
  const LatLongPyramid& pyramid;
  PrefilterLobe lobe;
  std::shared_ptr<const RadialTable> table;
  std::function<std::shared_ptr<const RadialTable>(double box)> correctedTable;
};

// The probe directions of the error estimate and, batch by batch on first use, their reference
// values and weights. Half the probes are a randomly rotated Fibonacci lattice (uniform); of the other
// half, half are drawn towards the bright parts of the environment (a texel of a coarse level by
// luminance x solid angle, then a lobe sample about it), half uniformly within the caps of 5 degrees
// about the bright sources (the texels brighter than 16 x the mean, merged within 2 degrees: a sun and
// its surroundings; all guided when there are none). Each is weighted by (1/4pi)/q(d), q the mixture's
// density. Batch b holds the lattice points i = b mod B and the guided and near-bright strata j = b mod B
// (B = 4 batches from 64 probes up), so batches 0 ... b together are a sample of the same mixture as
// all of them, and an estimate decided on the first batches pays only their reference sums.
class ProbeSet {
 public:
  ProbeSet(const ProbeSources& sources, const PrefilterOptions& options, double floor);
  ProbeSet(const ProbeSet&) = delete;
  ProbeSet& operator=(const ProbeSet&) = delete;
  int batches() const { return static_cast<int>(batchEnd_.size()); }
  // Probes [0, batchEnd(b)) are batches 0 ... b.
  int batchEnd(int batch) const { return batchEnd_[static_cast<std::size_t>(batch)]; }
  // Computes the reference and weight of every probe of batches 0 ... `batch` not yet computed.
  void extend(int batch);
  const Vec3& axis(int p) const { return axes_[static_cast<std::size_t>(p)]; }
  // Probes [0, ready()) have their reference and weight.
  int ready() const { return ready_; }
  const Rgb& reference(int p) const { return reference_[static_cast<std::size_t>(p)]; }
  double weight(int p) const { return weights_[static_cast<std::size_t>(p)]; }
  // The probe lies within a bright texel's cap (whichever group drew it).
  bool nearBright(int p) const { return nearBright_[static_cast<std::size_t>(p)] != 0; }
  double floor() const { return floor_; }

 private:
  // Puts the probes of each group (lattice, guided, near-bright) into the batches: batch b holds those
  // of index i = b mod B of every group.
  void arrangeBatches(const std::vector<Vec3>& lattice, const std::vector<Vec3>& guided, const std::vector<Vec3>& near);
  // Keeps the centres and probabilities of the texels the guided probes were drawn from (`cdf`:
  // luminance x solid angle over `level`'s texels, a running sum), for guidedDensity.
  void keepGuidedTexels(const LatLongLevel& level, const std::vector<double>& cdf);
  // Chooses how the reference on the probes is summed: the environment's own texels or a pyramid level.
  void prepareReference(const ProbeSources& sources);
  // The guided draws' density at d relative to the uniform density's, over the guided texels within
  // the lobe's support of d (the tabulated lobe is exactly zero beyond it).
  double guidedDensity(const Vec3& d) const;
  int capsHolding(const Vec3& d) const;
  PrefilterLobe lobe_;
  double floor_ = 0.0;
  std::vector<Vec3> axes_;
  std::vector<double> weights_;
  std::vector<unsigned char> nearBright_;
  std::vector<Rgb> reference_;
  std::vector<int> batchEnd_;
  int ready_ = 0, count_ = 0, uniformCount_ = 0, guided_ = 0, near_ = 0;
  // Guided draws: the bright texels' centres and their probabilities (luminance x solid angle, summing to 1).
  std::vector<Vec3> centres_;
  std::vector<double> probability_;
  // Near-bright draws: the caps' centres and cos of their angle.
  std::vector<Vec3> bright_;
  double capCos_ = 1.0;
  std::shared_ptr<const RadialTable> table_;
  std::optional<DirectSummer> pyramidSum_;
  std::optional<ReferenceSummer> ownTexels_;
};

struct ErrorEstimate {
  double rms = 0.0;        // solid-angle RMS of the relative error
  double highlight = 0.0;  // the larger of its value-weighted RMS and its RMS uniform over the bright caps
  double worst = 0.0;
  int probes = 0;
  double bound() const { return std::max(rms, highlight); }
};

// The error of `value` (an evaluator at an axis) on the probes, batch by batch: the solid-angle RMS of
// the relative error, its value-weighted RMS (weights times |reference|) and its RMS uniform over the
// caps about bright texels (near a sun the solid-angle RMS averages a highlight's large errors away,
// issue 22); the bound the largest. It stops at the first batch after which some mean square lies more
// than twice its standard error above target^2, or all lie below it once at least half the probes are
// read, and otherwise reads every probe. On the 1024 x 512 sky's gloss chain the first 128 probes put
// one level's error at 0.35 % where all 512 put it at 0.50 % (2 standard errors: the sun's rare large
// errors are easily missed), while 256 probes were within 6 % of all 512 at every candidate tried, so a
// candidate is accepted only from half the probes on.
ErrorEstimate estimate(const std::function<Rgb(const Vec3&)>& value, ProbeSet& probes, double target);

// The probes whose reference was computed, kept to measure the finished map's lookups.
struct ProbeCheck {
  std::vector<Vec3> axes;
  std::vector<Rgb> references;
  std::vector<double> weights;
  std::vector<bool> nearBright;
  double floor = 0.0;
};

// A filtered lobe: chooses the method (reference, or the fast candidates with auto's fallback)
// and evaluates it at every output texel. `check` gets the estimate's probes (prefilter_choice.cpp).
Image filterWithLobe(PrefilterInput& input, const PrefilterLobe& lobe, const Parameterization& map,
                     const PrefilterOptions& options, const Context& context, int threads, PrefilterSummary& summary,
                     std::optional<ProbeCheck>& check);

// The finished map as a renderer reads it: bilinear lookups at the probes against their reference, as
// the solid-angle RMS, the value-weighted RMS and the RMS over the bright sources' caps of the relative
// error, each with two standard errors to spare: lookupErrorEstimate. The probes saw the method at the
// texel centres' axes; the lookups add the texels' interpolation, which only the resolution changes
// (a sun's highlight a few texels wide, issue 22), so it is reported beside the estimate, not in it
// (prefilter_error.cpp).
void measureLookups(const Image& level0, const Parameterization& map, const PrefilterLobe& lobe,
                    const PrefilterOptions& options, const ProbeCheck& check, PrefilterSummary& summary);

}  // namespace brdfbake::detail

namespace brdfbake {
// prefilter() reading the environment, pyramid and mean |L| of `input` (made once for all the
// lobes prefiltered from it).
PrefilteredMap prefilter(detail::PrefilterInput& input, const PrefilterLobe& lobe, const PrefilterOptions& options,
                         const Context& context);
}  // namespace brdfbake
