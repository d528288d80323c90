#include "rangefuse/route/ScanLoader.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "CompactAttributes.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/surface/ColumnBands.h"
#include "rangefuse/surface/GridMerging.h"

namespace rangefuse {

namespace {

/// What the scan saw, on cells of about the merged grid's (the voxel's) scale. A depth
/// image's pixels without a return are measurements its camera did not make.
SightMap sightMapOf(const RangeGrid& grid, const ScanSurface& local, const SurfaceOptions& o,
                    const RangeNoise& noise, bool depthImage) {
  const double spacing = lateralSpacing(grid);
  const int shortSide = std::min(grid.cols, grid.rows);
  const int k = o.mergeTarget > 0 ? mergeFactor(spacing, o.mergeTarget, shortSide) : 1;
  // A station's lines of sight fan out in angles: cells of its (merged) angular step.
  SightMap map = grid.spherical ? SightMap::fromStation(local, k * angularSpacing(grid))
                 : grid.pinhole
                     ? SightMap::fromPinholeGrid(grid, k,
                                                 depthImage ? SightMap::NoReturn::DepthCamera
                                                            : SightMap::NoReturn::SawNothing)
                     : SightMap::fromSurface(local, std::max(o.mergeTarget, spacing), &grid);
  // A merged point is the mean of k x k cells: 1 / k of their noise.
  map.setNoise(noise, 1.0 / k);
  return map;
}

/// One band of a large PTX or E57 station: the rules from the scan's sample, then the band's own
/// columns.
PrismScan prepareBand(const io::ConfScan& c, const SurfaceOptions& options, double eps) {
  const ColumnReader read = [&](int first, int count) {
    return c.ptx ? io::readPtxColumns(c.path, *c.ptx, first, count)
                 : io::readE57Columns(c.path, *c.e57, first, count);
  };
  const int cols = c.ptx ? c.ptx->cols : c.e57->cols, rows = c.ptx ? c.ptx->rows : c.e57->rows;
  const BandRules rules = bandRules(read, cols, rows, options);
  PrismScan s;
  s.surface = buildBandSurface(read, rules, c.band, c.bands, options);
  s.limits = computePrismLimits(s.surface, eps);
  if (options.sightMap)
    s.sight = std::make_shared<SightMap>(SightMap::fromStation(s.surface, rules.angular));
  return s;
}

/// Only a depth camera's frames are smoothed. Its noise grows with depth² to several voxels on far
/// walls, where smoothing is what keeps them; a scanner's noise of about a voxel is averaged
/// better by the field and registration than by smoothing, which rounds its edges (decision 41).
/// Only they have flat blocks joined: a scanner's grids meet a voxel's accuracy to a few
/// hundredths, below the joins' tolerance (decision 42). Their normals are filtered apart
/// (decision 51).
SurfaceOptions optionsFor(const io::ConfScan& c, SurfaceOptions options) {
  if (!c.depth) options.smoothTarget = 0, options.flatTolerance = 0;
  if (c.depth && options.depthNormalPasses >= 0) options.normalPasses = options.depthNormalPasses;
  return options;
}

PrismScan prepareScan(const io::ConfScan& c, const SurfaceOptions& given, const InputLimits& limits,
                      double eps) {
  if (c.bands > 1) return prepareBand(c, given, eps);
  const SurfaceOptions options = optionsFor(c, given);
  PrismScan s;
  const RangeGrid grid = io::readScanGrid(c, limits);
  // Measured once: smoothing, the sight map's tests and tracking's weights read the same curve.
  if (given.measureNoise || c.depth || given.sightMap) s.noise = RangeNoise::measure(grid);
  const RangeNoise& noise = s.noise;
  s.surface = buildScanSurface(grid, Pose{}, options, &noise);
  s.limits = computePrismLimits(s.surface, eps);
  if (options.sightMap)
    s.sight = std::make_shared<SightMap>(
        sightMapOf(grid, s.surface, options, noise, c.depth.has_value()));
  return s;
}

}  // namespace

PrismScan loadScan(const io::ConfScan& c, const SurfaceOptions& options, const InputLimits& limits,
                   double eps) {
  faultPoint("read", c.path);
  return prepareScan(c, options, limits, eps);
}

std::vector<PrismScan> loadScans(const std::vector<const io::ConfScan*>& scans,
                                 const SurfaceOptions& options, const InputLimits& limits,
                                 double eps, int threads) {
  // Fault points count calls and ask MPI for the rank: the main thread passes them in order.
  for (const io::ConfScan* c : scans) faultPoint("read", c->path);
  std::vector<PrismScan> out(scans.size());
  parallelFor(scans.size(), threads,
              [&](size_t k) { out[k] = prepareScan(*scans[k], options, limits, eps); });
  return out;
}

uint64_t scanBytes(const PrismScan& s) {
  const uint64_t perPoint = 2 * sizeof(Eigen::Vector3d) + sizeof(double);
  const uint64_t perTriangle = sizeof(Triangle) + sizeof(std::array<double, 2>);
  return perPoint * s.surface.points.size() + sizeof(Colour) * s.surface.colours.size() +
         sizeof(Texel) * s.surface.texels.cells.size() +
         sizeof(std::array<int32_t, 2>) * s.surface.blocks.size() +
         perTriangle * s.surface.triangles.size();
}

PrismScan placeScan(PrismScan s, const Pose& pose) {
  for (auto& p : s.surface.points) p = pose.apply(p);
  for (auto& n : s.surface.normals) n = pose.rotate(n);
  s.noise = RangeNoise{};  // its depths are the scan frame's
  if (s.sight) {
    s.sight = std::make_shared<SightMap>(*s.sight);  // copies of the scan may sit elsewhere
    s.sight->place(pose);
  }
  return s;
}

namespace {

template <class T>
void roundToFloats(std::vector<T>& v) {
  double* x = reinterpret_cast<double*>(v.data());
  for (size_t k = 0; k < v.size() * sizeof(T) / sizeof(double); ++k)
    x[k] = static_cast<float>(x[k]);
}

/// The largest |d| of the prisms' limits: their envelope's half-width, eps, unless every
/// prism is truncated (0 without triangles).
double envelope(const PrismLimits& limits) {
  double eps = 0;
  for (const auto& [lo, hi] : limits) eps = std::max({eps, -lo, hi});
  return eps;
}

}  // namespace

PrismScan compactScan(PrismScan s) {
  if (s.compact() || s.surface.points.empty()) return s;
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : s.surface.points) box.extend(p);
  const Eigen::Vector3d centre = box.center();
  const double half = std::max((box.max() - centre).maxCoeff(), (centre - box.min()).maxCoeff());
  const double far = std::max(centre.cwiseAbs().maxCoeff(), half);
  // Offsets within 2^23 quanta of the centre's lattice point (24 bits packed) where that step
  // is under 2^-14 of the prisms' envelope, else within 2^30, however far from the world's
  // origin the scan lies (a float's step would grow with that distance); and no finer than the
  // centre's own step, so that origin + n * quantum is exact.
  const auto step = [](double x, int bits) {
    return std::ldexp(1.0, std::ilogb(std::max(x, 1e-100)) + 1 - bits);  // 1/quantum finite
  };
  const double coarse = step(half, 23);
  s.quantum = std::max(coarse <= std::ldexp(envelope(s.limits), -14) ? coarse : step(half, 30),
                       step(far, 52));
  s.origin = (centre / s.quantum).array().round().matrix() * s.quantum;
  const double perQuantum = 1 / s.quantum;  // a power of two: exact
  for (Eigen::Vector3d& p : s.surface.points)
    for (int c = 0; c < 3; ++c)
      p[c] = s.origin[c] + std::nearbyint((p[c] - s.origin[c]) * perQuantum) * s.quantum;
  for (Eigen::Vector3d& n : s.surface.normals) n = internal::quantisedNormal(n);
  for (double& c : s.surface.confidence) c = internal::quantisedConfidence(c);
  roundToFloats(s.limits);
  return s;
}

}  // namespace rangefuse
