#include <gtest/gtest.h>

#include <Eigen/LU>
#include <map>
#include <random>

#include "prism/PrismSolve.h"
#include "rangefuse/prism/PrismRaster.h"

using namespace rangefuse;

namespace {

const std::array<Eigen::Vector3d, 3> kTri = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                             Eigen::Vector3d(0, 1, 0)};
const std::array<double, 3> kW = {0.2, 0.6, 1.0};

std::array<Eigen::Vector3d, 3> same(const Eigen::Vector3d& n) {
  return {n, n, n};
}

}  // namespace

TEST(CubicRoots, KnownRootsAndDegenerateLeadingTerms) {
  double r[3];
  const double c[4] = {-6, 11, -6, 1};  // (x-1)(x-2)(x-3)
  ASSERT_EQ(internal::cubicRootsInRange(c, 0, 4, r), 3);
  EXPECT_NEAR(r[0], 1, 1e-12);
  EXPECT_NEAR(r[1], 2, 1e-12);
  EXPECT_NEAR(r[2], 3, 1e-12);
  ASSERT_EQ(internal::cubicRootsInRange(c, 1.5, 2.5, r), 1);
  const double q[4] = {-2, 0, 2, 0};  // quadratic 2x^2 - 2
  ASSERT_EQ(internal::cubicRootsInRange(q, -5, 5, r), 2);
  EXPECT_NEAR(r[0], -1, 1e-12);
  EXPECT_NEAR(r[1], 1, 1e-12);
  const double l[4] = {1, 4, 0, 0};  // linear
  ASSERT_EQ(internal::cubicRootsInRange(l, -1, 1, r), 1);
  EXPECT_NEAR(r[0], -0.25, 1e-15);
}

TEST(CubicRoots, EveryRootInRangeAgainstDenseSampling) {
  // Nearly linear cubics take the monotonic path, the others the general one: both must find
  // each sign change a fine sampling of the range sees.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int roots = 0;
  for (int t = 0; t < 2000; ++t) {
    const double curved = t % 2 ? 1.0 : 1e-3;
    const double c[4] = {u(rng), 1 + u(rng), curved * u(rng), curved * u(rng)};
    double r[3];
    const int n = internal::cubicRootsInRange(c, -1, 1, r);
    auto f = [&](double x) { return ((c[3] * x + c[2]) * x + c[1]) * x + c[0]; };
    int changes = 0;
    for (int i = 0; i < 4000; ++i)
      if ((f(-1 + i / 2000.0) < 0) != (f(-1 + (i + 1) / 2000.0) < 0)) ++changes;
    ASSERT_EQ(n, changes) << "cubic " << t;
    for (int k = 0; k < n; ++k) EXPECT_LT(std::abs(f(r[k])), 1e-12) << "cubic " << t;
    roots += n;
  }
  EXPECT_GT(roots, 1000);
}

TEST(CubicRoots, RootBracketsCountEveryRootAndHoldTheLast) {
  // Cubics that turn in range, as a tilted prism's do far from its generator: the count must
  // be cubicRootsInRange's, and the last bracket must hold its last root.
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  int turning = 0, several = 0;
  for (int t = 0; t < 4000; ++t) {
    const double c[4] = {0.5 * u(rng), 0.3 * u(rng), u(rng), u(rng)};
    double r[3], a = 0, b = 0;
    const int n = internal::cubicRootsInRange(c, -1, 1, r),
              m = internal::rootBrackets(c, -1, 1, a, b);
    ASSERT_EQ(m, n) << "cubic " << t;
    if (!internal::cubicMonotonicIn(c, -1, 1)) ++turning;
    if (n > 1) ++several;
    if (n > 0) {
      EXPECT_LE(a, r[n - 1]) << "cubic " << t;
      EXPECT_GE(b, r[n - 1]) << "cubic " << t;
    }
  }
  EXPECT_GT(turning, 2000);
  EXPECT_GT(several, 200);
  double a, b;
  const double root[4] = {0, 1, 0, -1};  // x - x^3: roots -1, 0, 1; -1 on the range's end
  EXPECT_EQ(internal::rootBrackets(root, -1, 2, a, b), -1);
}

TEST(Prism, CubicIsTheDeterminantOfTheIsoTriangle) {
  // Eq. 6's det[T(d) - x], expanded once per prism, against the determinant itself.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int t = 0; t < 100; ++t) {
    std::array<Eigen::Vector3d, 3> p, n;
    for (int k = 0; k < 3; ++k) {
      p[k] = Eigen::Vector3d(u(rng), u(rng), u(rng));
      n[k] = Eigen::Vector3d(u(rng), u(rng), 2 + u(rng)).normalized();
    }
    const Prism prism = makePrism(p, n, kW, 0.5);
    const internal::PrismCubic cubic(prism);
    const Eigen::Vector3d x(u(rng), u(rng), u(rng));
    for (double d : {-0.4, 0.0, 0.3}) {
      Eigen::Matrix3d m;
      for (int k = 0; k < 3; ++k) m.col(k) = p[k] + d * n[k] - x;
      const Eigen::Vector3d w = p[0] - x;
      const double c = cubic.N.dot(w) + d * (cubic.Nn + cubic.K.dot(w)) +
                       d * d * (cubic.Kn + cubic.L.dot(w)) + d * d * d * cubic.Ln;
      EXPECT_NEAR(c, m.determinant(), 1e-12);
    }
  }
}

TEST(Prism, PlaneDistanceIsHeight) {
  Prism p = makePrism(kTri, same({0, 0, 1}), kW, 0.5);
  EXPECT_EQ(p.dMin, -0.5);
  EXPECT_EQ(p.dMax, 0.5);
  PrismHit h;
  for (double z : {0.25, -0.4, 0.0}) {
    ASSERT_TRUE(solvePrismDistance(p, Eigen::Vector3d(0.2, 0.3, z), h));
    EXPECT_NEAR(h.d, z, 1e-14);
    EXPECT_LT((h.bary - Eigen::Vector3d(0.5, 0.2, 0.3)).norm(), 1e-14);
    EXPECT_LT((h.closest - Eigen::Vector3d(0.2, 0.3, 0)).norm(), 1e-14);
    EXPECT_LT((h.gradient - Eigen::Vector3d(0, 0, 1)).norm(), 1e-14);
    EXPECT_NEAR(h.weight, 0.5 * 0.2 + 0.2 * 0.6 + 0.3 * 1.0, 1e-14);
  }
  EXPECT_FALSE(solvePrismDistance(p, Eigen::Vector3d(0.2, 0.3, 0.6), h));  // beyond envelope
  EXPECT_FALSE(solvePrismDistance(p, Eigen::Vector3d(0.8, 0.8, 0.1), h));  // beside triangle
}

TEST(Prism, TiltedPlaneDistanceIsSignedDistanceToPlane) {
  const Eigen::Vector3d n = Eigen::Vector3d(-0.3, -0.2, 1).normalized();  // z = 0.3x + 0.2y
  auto onPlane = [](double x, double y) { return Eigen::Vector3d(x, y, 0.3 * x + 0.2 * y); };
  Prism p = makePrism({onPlane(0, 0), onPlane(2, 0), onPlane(0, 2)}, same(n), kW, 1.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1), h(-0.9, 0.9);
  for (int i = 0; i < 100; ++i) {
    double a = u(rng), b = u(rng) * (1 - a), d = h(rng);
    Eigen::Vector3d x = onPlane(2 * a, 2 * b) + d * n;
    PrismHit hit;
    ASSERT_TRUE(solvePrismDistance(p, x, hit));
    EXPECT_NEAR(hit.d, d, 1e-12);
    EXPECT_NEAR(hit.d, n.dot(x - onPlane(0, 0)), 1e-12);
  }
}

TEST(Prism, DistanceAlongInterpolatedNormals) {
  const std::array<Eigen::Vector3d, 3> n = {Eigen::Vector3d(0.3, 0, 1).normalized(),
                                            Eigen::Vector3d(-0.2, 0.25, 1).normalized(),
                                            Eigen::Vector3d(0.1, -0.3, 1).normalized()};
  Prism p = makePrism(kTri, n, kW, 0.5);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1), h(-0.3, 0.3);
  for (int i = 0; i < 200; ++i) {
    double b1 = u(rng), b2 = u(rng) * (1 - b1), d = h(rng);
    Eigen::Vector3d b(1 - b1 - b2, b1, b2);
    // x lies at height d along the interpolated normal above barycentric point b (Eq. 4).
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) x += b[k] * (kTri[k] + d * n[k]);
    PrismHit hit;
    ASSERT_TRUE(solvePrismDistance(p, x, hit));
    EXPECT_NEAR(hit.d, d, 1e-12);
    EXPECT_LT((hit.bary - b).norm(), 1e-10);
    Eigen::Vector3d nc = b[0] * n[0] + b[1] * n[1] + b[2] * n[2];
    EXPECT_LT((x - hit.closest - d * nc).norm(), 1e-12);
  }
}

TEST(Prism, ConvergingNormalsAreTruncatedBeforeTheTwist) {
  // Normals meet at the apex (1/3, 1/3, 0.2), 0.529 from p0: the prism must stop before.
  const Eigen::Vector3d apex(1.0 / 3, 1.0 / 3, 0.2);
  std::array<Eigen::Vector3d, 3> n;
  for (int k = 0; k < 3; ++k) n[k] = (apex - kTri[k]).normalized();
  Prism p = makePrism(kTri, n, kW, 1.0);
  EXPECT_LE(p.dMax, (apex - kTri[0]).norm() + 1e-12);
  EXPECT_GT(p.dMax, 0.0);
  EXPECT_EQ(p.dMin, -1.0);  // diverging below: no twist inside the envelope
  for (double d = p.dMin; d <= p.dMax; d += 0.01) {
    Eigen::Vector3d q[3];
    for (int k = 0; k < 3; ++k) q[k] = kTri[k] + d * n[k];
    EXPECT_GT((q[1] - q[0]).cross(q[2] - q[0]).z(), 0) << "T(d) flipped at d=" << d;
  }
  PrismHit hit;
  EXPECT_FALSE(solvePrismDistance(p, apex + Eigen::Vector3d(0, 0, 0.3), hit));
}

TEST(Prism, RowRasterizationFindsExactlyTheBruteForceVoxels) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(-2, 2), tilt(-0.5, 0.5);
  VoxelGrid grid;
  grid.voxel = 0.37;
  grid.origin = Eigen::Vector3d(0.01, -0.02, 0.03);
  size_t total = 0;
  for (int t = 0; t < 300; ++t) {
    std::array<Eigen::Vector3d, 3> p, n;
    for (auto& v : p) v = Eigen::Vector3d(pos(rng), pos(rng), pos(rng) * 0.3);
    Eigen::Vector3d fn = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
    for (auto& v : n) v = (fn + Eigen::Vector3d(tilt(rng), tilt(rng), tilt(rng))).normalized();
    if (t % 10 == 0) {  // flat on the lattice, straight normals: side slabs parallel to the rows
      for (auto& v : p) v.z() = 0.25 * (t / 10 % 4);
      n.fill(Eigen::Vector3d::UnitZ());
      if (t % 20 == 0) std::swap(p[1], p[2]);  // and facing down
    }
    Prism prism = makePrism(p, n, kW, 3 * grid.voxel);
    std::map<std::array<int, 3>, double> fast, slow;
    rasterizePrism(prism, grid, [&](const VoxelIndex& v, const PrismHit& h) {
      fast[{v.x(), v.y(), v.z()}] = h.d;
    });
    rasterizePrismBruteForce(prism, grid, [&](const VoxelIndex& v, const PrismHit& h) {
      slow[{v.x(), v.y(), v.z()}] = h.d;
    });
    // The same voxels; distances to rounding (the rows solve in batches, the reference alone).
    ASSERT_EQ(fast.size(), slow.size()) << "triangle " << t;
    for (const auto& [voxel, d] : slow) {
      ASSERT_EQ(fast.count(voxel), 1u) << "triangle " << t;
      ASSERT_NEAR(fast[voxel], d, 1e-12) << "triangle " << t;
    }
    total += slow.size();
  }
  EXPECT_GT(total, 3000u);  // the comparison covered real work
}

TEST(Prism, BatchedFeetMatchOnePointAtATime) {
  // Straight, tilted (past the quick path) and flat (no area) prisms, points inside, beside,
  // above and below: solveFeet must decide as solvePrismFoot does, and find the same foot.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> pos(-1, 1), u01(0, 1);
  int inside = 0, outside = 0;
  for (int t = 0; t < 600; ++t) {
    const double tilt = t % 3 == 0 ? 0.02 : t % 3 == 1 ? 0.3 : 0.9;
    std::array<Eigen::Vector3d, 3> p = kTri, n;
    for (auto& v : p) v.z() += 0.1 * pos(rng);
    if (t % 50 == 0) p[2] = 0.5 * (p[0] + p[1]);  // a triangle without area
    for (auto& v : n)
      v = (Eigen::Vector3d::UnitZ() + tilt * Eigen::Vector3d(pos(rng), pos(rng), pos(rng)))
              .normalized();
    const Prism prism = makePrism(p, n, kW, 0.5);
    const internal::PrismCubic cubic(prism);
    Eigen::Vector3d points[internal::kFootBatch];
    const int count = 1 + t % internal::kFootBatch;
    for (int i = 0; i < count; ++i)
      points[i] = Eigen::Vector3d(1.4 * u01(rng) - 0.2, 1.4 * u01(rng) - 0.2, 0.7 * pos(rng));
    PrismFoot feet[internal::kFootBatch];
    bool in[internal::kFootBatch];
    internal::solveFeet(prism, cubic, points, count, feet, in);
    for (int i = 0; i < count; ++i) {
      PrismFoot one;
      const bool alone = internal::solvePrismFoot(prism, cubic, points[i], one);
      ASSERT_EQ(in[i], alone) << "prism " << t << " point " << i;
      if (!alone) {
        ++outside;
        continue;
      }
      ++inside;
      EXPECT_NEAR(feet[i].d, one.d, 1e-12) << "prism " << t << " point " << i;
      EXPECT_LT((feet[i].bary - one.bary).norm(), 1e-9) << "prism " << t << " point " << i;
    }
  }
  EXPECT_GT(inside, 500);  // both answers were tried often
  EXPECT_GT(outside, 500);
}

TEST(Prism, QuickExitOnlyWhereEveryEdgeSurfaceMeetingIsOutsideTheEnvelope) {
  // Brute force: sign changes of det[X(u), Y(u), n_i] over a fine u grid, refined by bisection,
  // are the meetings; each gives d from X + d Y - v n_i = 0. The quick exit must never skip a
  // meeting with |d| <= eps, and must fire for most nearly parallel normals (else it buys
  // nothing).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u01(0, 1), sym(-1, 1);
  int exits = 0, nearlyParallel = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const double tilt = trial % 2 ? 0.05 : 0.8;  // radians-ish spread of the normals
    std::array<Eigen::Vector3d, 3> p, n;
    for (int k = 0; k < 3; ++k) {
      p[k] = Eigen::Vector3d(u01(rng), u01(rng), 0.1 * sym(rng));
      n[k] = (Eigen::Vector3d::UnitZ() + tilt * Eigen::Vector3d(sym(rng), sym(rng), sym(rng)))
                 .normalized();
    }
    const double eps = 0.05 + 2 * u01(rng);
    const Eigen::Vector3d A = p[1] - p[0], B = p[2] - p[1];
    if (!internal::crossingBeyond(A, B, n[1], n[2], n[0], eps)) continue;
    ++exits;
    nearlyParallel += trial % 2;
    auto det = [&](double u) { return (A + u * B).dot((n[1] + u * (n[2] - n[1])).cross(n[0])); };
    const int steps = 2000;
    for (int s = 0; s < steps; ++s) {
      double lo = double(s) / steps, hi = double(s + 1) / steps;
      if ((det(lo) < 0) == (det(hi) < 0)) continue;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        ((det(mid) < 0) == (det(lo) < 0) ? lo : hi) = mid;
      }
      const Eigen::Vector3d X = A + lo * B, Y = n[1] + lo * (n[2] - n[1]);
      Eigen::Matrix<double, 3, 2> M;
      M << Y, -n[0];
      const Eigen::Vector2d dv = M.colPivHouseholderQr().solve(-X);
      EXPECT_GT(std::abs(dv[0]), eps) << "trial " << trial << " u " << lo;
    }
  }
  EXPECT_GT(nearlyParallel, 1500);   // of 2000 nearly parallel trials
  EXPECT_GT(exits, nearlyParallel);  // and some of the strongly turning ones
}

TEST(Prism, EnvelopeClearanceClearsOnlyWhatTheQuickExitClears) {
  // makePrism skips truncateAtEdgeSurface for a vertex the clearance test clears, so the prism
  // is the same bits only if crossingBeyond (truncateAtEdgeSurface's own quick exit) would have
  // cleared it too. Brute force over random triangles, with the envelope set about where the
  // tests decide (eps within 1 % of the height over the tilt), at scales from 1e-3 to 1e3, and
  // degenerate ones: collinear corners, a zero normal, a normal that is not a number.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u01(0, 1), sym(-1, 1);
  int cleared = 0, quick = 0, clearedNearlyFlat = 0, quickNearlyFlat = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double scale = std::pow(10.0, 6 * u01(rng) - 3);
    const double tilt = std::pow(10.0, -3 * u01(rng));  // normals' spread, radians about
    std::array<Eigen::Vector3d, 3> p, n;
    for (int k = 0; k < 3; ++k) {
      p[k] = scale * Eigen::Vector3d(u01(rng), u01(rng), 0.1 * sym(rng));
      n[k] = (Eigen::Vector3d::UnitZ() + tilt * Eigen::Vector3d(sym(rng), sym(rng), sym(rng)))
                 .normalized();
    }
    const int kind = trial % 10;
    if (kind == 7) p[2] = p[0] + 0.5 * (p[1] - p[0]);  // collinear: no height
    if (kind == 8) n[trial % 3].setZero();
    if (kind == 9) n[trial % 3].x() = NAN;
    // eps near the height over the tilt of vertex 0, where either test may go either way.
    const Eigen::Vector3d X = (p[1] - p[0]).cross(p[2] - p[0]);
    const double height = X.norm() / (p[2] - p[1]).norm();
    const double eps = height / std::max(tilt, 1e-9) * (1 + 0.01 * sym(rng));
    const internal::EnvelopeClearance clearance(p, n, eps);
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3, b = (i + 2) % 3;
      const bool exits = internal::crossingBeyond(p[a] - p[i], p[b] - p[a], n[a], n[b], n[i], eps);
      if (clearance.clear[i]) {
        EXPECT_TRUE(exits) << "trial " << trial << " vertex " << i;
        ++cleared;
        clearedNearlyFlat += tilt < 0.01;
      }
      quick += exits;
      quickNearlyFlat += exits && tilt < 0.01;
    }
    if (kind >= 7) {
      EXPECT_FALSE(clearance.clear[0] && clearance.clear[1] && clearance.clear[2]);
    }
  }
  // It must clear most of what the quick exit clears (else it buys nothing).
  EXPECT_GT(cleared, quick / 2);
  EXPECT_GT(clearedNearlyFlat, quickNearlyFlat / 2);
}

TEST(Prism, MakePrismTruncatesAsEachVertexTestSays) {
  // A triangle whose normals turn sharply is truncated (its vertices are not cleared), one
  // whose normals are parallel keeps its whole envelope (all are), and the same triangle with
  // the clearance test's answers gives the same limits either way.
  const std::array<Eigen::Vector3d, 3> flat = same(Eigen::Vector3d::UnitZ());
  const internal::EnvelopeClearance parallel(kTri, flat, 0.5);
  EXPECT_TRUE(parallel.clear[0] && parallel.clear[1] && parallel.clear[2]);
  const Prism whole = makePrism(kTri, flat, kW, 0.5);
  EXPECT_EQ(whole.dMin, -0.5);
  EXPECT_EQ(whole.dMax, 0.5);
  const std::array<Eigen::Vector3d, 3> fan = {Eigen::Vector3d(-1, -1, 1).normalized(),
                                              Eigen::Vector3d(1, 0, 1).normalized(),
                                              Eigen::Vector3d(0, 1, 1).normalized()};
  const internal::EnvelopeClearance turning(kTri, fan, 2.0);
  EXPECT_FALSE(turning.clear[0] && turning.clear[1] && turning.clear[2]);
  const Prism cut = makePrism(kTri, fan, kW, 2.0);
  EXPECT_TRUE(cut.dMin > -2.0 || cut.dMax < 2.0);  // the normals' lines meet inside
}
