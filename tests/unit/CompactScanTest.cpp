// A streamed field's scans are made compact once placed (decisions 45, 58): points on a lattice
// of their own, normals rounded to 32-bit octahedral codes' directions, confidences to 16-bit
// fractions and limits to floats. The field of the compact scans
// against the field of the same scans in doubles, voxel by voxel, on the real bunny, a depth
// camera's sequence and a scanner's PTX station, within the tolerance the decision states; and
// the compact values survive routing's packing exactly, far from the origin too.
#include <gtest/gtest.h>

#include <cmath>

#include "TempDir.h"
#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/io/DepthSequence.h"
#include "rangefuse/io/Ptx.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/route/ScanRouting.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;

namespace {

/// The scans `list` names, prepared as `fuse` prepares them at `voxel` and placed.
std::vector<PrismScan> placedScans(const std::string& list, double voxel) {
  FuseOptions o;
  o.scans = list;
  o.field.voxel = voxel;
  const RunSettings s = runSettings(o);
  std::vector<PrismScan> scans;
  for (const io::ConfScan& c : io::readScanList(list).scans)
    scans.push_back(placeScan(loadScan(c, s.read.surface, s.read.limits, s.read.eps), c.pose));
  return scans;
}

BrickStore::Sums fieldOf(const std::vector<PrismScan>& scans, const BrickLayout& layout) {
  BrickStore store(layout, 0);
  PrismIntegrator integrator(store);
  for (const PrismScan& s : scans) integrator.addScan(s);
  return store.sums();
}

struct Difference {
  size_t sampled = 0;  ///< voxels both fields sampled
  size_t onlyOne = 0;  ///< voxels one field sampled and the other did not
  double largest = 0;  ///< largest |d - d'| where both did, in voxels
  size_t beyond = 0;   ///< voxels where it passes 1e-3 voxel
};

/// The fields of the scans and of their compact copies, on the doubles' bricks.
Difference compactAgainstDouble(const std::vector<PrismScan>& scans, double voxel, double eps) {
  std::vector<PrismScan> compact;
  for (const PrismScan& s : scans) compact.push_back(compactScan(s));
  const BrickLayout layout = planBricks(scans, fitGrid(scans, voxel, 8, eps), 1);
  const auto a = fieldOf(scans, layout), b = fieldOf(compact, layout);
  Difference diff;
  for (size_t i = 0; i < a.size(); ++i) {
    if ((a[i].w > 0) != (b[i].w > 0)) ++diff.onlyOne;
    if (!(a[i].w > 0 && b[i].w > 0)) continue;
    ++diff.sampled;
    const double d = std::abs(a[i].wd / a[i].w - b[i].wd / b[i].w) / voxel;
    diff.largest = std::max(diff.largest, d);
    diff.beyond += d > 1e-3;
  }
  return diff;
}

/// Decision 58's tolerance: where both fields sample a voxel, its distance moves by less than a
/// thousandth of a voxel in all but one voxel in 10^4 (a voxel whose nearest triangle changes
/// to its neighbour, a tie the normals' rounding broke), and by under a tenth of a voxel in
/// every one; no more than one voxel in 10^4 gains or loses its sample (its centre on a prism's
/// envelope).
void expectWithinTolerance(const Difference& d, const std::string& set) {
  ASSERT_GT(d.sampled, 10000u) << set;
  EXPECT_LE(d.beyond, d.sampled / 10000) << set << ": largest " << d.largest << " voxel";
  EXPECT_LT(d.largest, 0.1) << set;
  EXPECT_LE(d.onlyOne, d.sampled / 10000) << set;
}

/// The scan with only the points its triangles use, values unchanged (packed in doubles).
PrismScan usedOnly(const PrismScan& scan) {
  return unpackedScan(packedScan(scan));
}

double epsOf(double voxel) {
  FuseOptions o;
  o.field.voxel = voxel;
  return runSettings(o).read.eps;
}

}  // namespace

TEST(CompactScan, TheRealBunnysFieldMovesWithinTheTolerance) {
  const double voxel = 0.002;
  const std::vector<PrismScan> scans = placedScans(RANGEFUSE_TEST_DATA "/bunny/bun.conf", voxel);
  expectWithinTolerance(compactAgainstDouble(scans, voxel, epsOf(voxel)), "bunny");
}

TEST(CompactScan, ADepthSequencesFieldMovesWithinTheTolerance) {
  // 12 frames of 160 x 120 around a scene 1.2 m across, noise growing with depth squared.
  const double voxel = 0.01;
  ScanSettings s;
  s.views = 12, s.width = 160, s.height = 120, s.voxel = voxel, s.noise = 0.5;
  s.depthNoise = true, s.path = ViewPath::Orbit;
  TriangleMesh scene = makeComposite();
  for (Eigen::Vector3d& v : scene.vertices) v *= 0.01;
  const SyntheticSet set = scanMesh(scene, s);
  std::vector<io::DepthFrame> frames;
  for (const SyntheticScan& sc : set.scans)
    frames.push_back({io::depthImage(sc.grid, 1e-3), io::cameraPose(sc.truth)});
  const test::TempDir dir;
  io::writeTumSequence(dir.file("tum"), frames, io::depthCamera(set.scans[0].grid, 1e-3));
  const std::vector<PrismScan> scans = placedScans(dir.file("tum"), voxel);
  expectWithinTolerance(compactAgainstDouble(scans, voxel, epsOf(voxel)), "depth sequence");
}

TEST(CompactScan, APtxStationsFieldMovesWithinTheTolerance) {
  // A station of 480 x 200 in the synthetic room (8 m across), 5 cm voxels.
  const double voxel = 0.05;
  ScanSettings s;
  s.views = 1, s.width = 480, s.height = 200, s.voxel = voxel, s.noise = 0.3;
  s.path = ViewPath::Stations;
  const SyntheticSet set = scanMesh(makeRoom(), s);
  const test::TempDir dir;
  io::writePtx(dir.file("room.ptx"), {set.scans[0].grid}, {set.scans[0].truth});
  const std::vector<PrismScan> scans = placedScans(dir.file("room.ptx"), voxel);
  expectWithinTolerance(compactAgainstDouble(scans, voxel, epsOf(voxel)), "PTX station");
}

TEST(CompactScan, FarFromTheOriginPointsMoveByHalfAQuantumAndPackExactly) {
  // A scan at map coordinates (5,000 km north): a float's step there is half a metre, the
  // lattice's is the scan's extent over 2^23 (its prisms' envelope spans 2^20 of those steps);
  // a scan whose prisms' envelope is under 2^14 of that step takes the centre's own double
  // step, 2^-29 m (its extent over 2^30 would be finer).
  PrismScan scan = placedScans(RANGEFUSE_TEST_DATA "/bunny/bun.conf", 0.004).front();
  for (Eigen::Vector3d& p : scan.surface.points) p += Eigen::Vector3d(4.5e5, 5.0e6, 300);
  PrismScan thin = scan;
  for (auto& [lo, hi] : thin.limits) lo = -1e-12, hi = 1e-12;
  for (const auto& [s, quantum] : {std::pair{scan, 0x1p-26}, std::pair{thin, 0x1p-29}}) {
    const PrismScan compact = compactScan(usedOnly(s));
    ASSERT_TRUE(compact.compact());
    EXPECT_EQ(compact.quantum, quantum);  // the bunny's half-extent is 6-12 cm
    const PrismScan used = usedOnly(s);
    for (size_t k = 0; k < used.surface.points.size(); ++k)
      ASSERT_LE((used.surface.points[k] - compact.surface.points[k]).cwiseAbs().maxCoeff(),
                compact.quantum / 2);
    EXPECT_EQ(unpackedScan(packedScan(compact)).surface.points, compact.surface.points);
  }
}

TEST(CompactScan, OffsetsPackIn24BitsWhereAllFitAndIn32Else) {
  // A compact scan made by hand: one triangle at offsets -2^23 and 2^23 - 1, then one past.
  PrismScan scan;
  scan.quantum = 0x1p-20;
  scan.origin = Eigen::Vector3d(1, -2, 0.5);
  const double q = scan.quantum, edge = 0x1p23;
  scan.surface.points = {scan.origin + q * Eigen::Vector3d(-edge, 0, edge - 1),
                         scan.origin + q * Eigen::Vector3d(edge - 1, -edge, 5),
                         scan.origin + q * Eigen::Vector3d(-1, 1, -edge)};
  scan.surface.normals.assign(3, Eigen::Vector3d(0, 0, 1));
  scan.surface.confidence.assign(3, 1.0);
  scan.surface.triangles = {{0, 1, 2}};
  scan.limits = {{-0.25, 0.25}};
  const std::vector<char> fits = packedScan(scan);
  EXPECT_EQ(unpackedScan(fits).surface.points, scan.surface.points);
  scan.surface.points[2].y() = scan.origin.y() + q * edge;
  const std::vector<char> past = packedScan(scan);
  EXPECT_EQ(unpackedScan(past).surface.points, scan.surface.points);
  EXPECT_EQ(past.size(), fits.size() + 9);  // a byte more for each of 9 offsets
}

TEST(CompactScan, CompactScansPackInUnder35PercentOfTheBytesAndComeBackExactly) {
  const std::vector<PrismScan> scans = placedScans(RANGEFUSE_TEST_DATA "/bunny/bun.conf", 0.004);
  const PrismScan& scan = scans.front();
  const PrismScan small = compactScan(usedOnly(scan));
  ASSERT_TRUE(small.compact());
  EXPECT_NE(small.surface.points, scan.surface.points) << "rounding moved no point";
  EXPECT_EQ(compactScan(small).surface.points, small.surface.points);
  const std::vector<char> asCompact = packedScan(small), asDoubles = packedScan(scan);
  EXPECT_LT(asCompact.size(), asDoubles.size() * 7 / 20);
  const PrismScan back = unpackedScan(asCompact);
  EXPECT_TRUE(back.compact());
  EXPECT_EQ(back.quantum, small.quantum);
  EXPECT_EQ(back.origin, small.origin);
  EXPECT_EQ(back.surface.points, small.surface.points);
  EXPECT_EQ(back.surface.normals, small.surface.normals);
  EXPECT_EQ(back.surface.confidence, small.surface.confidence);
  EXPECT_EQ(back.surface.triangles, small.surface.triangles);
  EXPECT_EQ(back.limits, small.limits);
  // A scan in doubles goes as doubles: nothing lost either.
  const PrismScan whole = unpackedScan(asDoubles);
  EXPECT_FALSE(whole.compact());
  EXPECT_EQ(whole.limits, scan.limits);
  EXPECT_EQ(whole.surface.triangles.size(), scan.surface.triangles.size());
}
