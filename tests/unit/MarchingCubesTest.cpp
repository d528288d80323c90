#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "rangefuse/mesh/MarchingCubes.h"

using namespace rangefuse;

namespace {

FieldBlock sphereBlock(int cells, const Eigen::Vector3d& centre, double radius) {
  FieldBlock b;
  b.base = VoxelIndex(0, 0, 0);
  b.cells = cells;
  for (int z = 0; z <= cells; ++z)
    for (int y = 0; y <= cells; ++y)
      for (int x = 0; x <= cells; ++x)
        b.values.push_back(static_cast<float>((Eigen::Vector3d(x, y, z) - centre).norm() - radius));
  return b;
}

double enclosedVolume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.faces)
    v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  return v;
}

/// Every directed edge appears once and its reverse once: closed and consistently oriented.
void expectClosedOriented(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : m.faces)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, count] : directed) {
    ASSERT_EQ(count, 1) << "edge used twice in one direction";
    auto rev = directed.find({e.second, e.first});
    ASSERT_NE(rev, directed.end()) << "boundary edge: mesh not closed";
  }
}

/// The eight 8^3-cube blocks of a 16^3-cube block, in z-major order of their corners.
std::vector<FieldBlock> octants(const FieldBlock& whole) {
  std::vector<FieldBlock> blocks(8);
  for (int o = 0; o < 8; ++o) {
    FieldBlock& b = blocks[o];
    b.base = VoxelIndex(8 * (o & 1), 8 * ((o >> 1) & 1), 8 * (o >> 2));
    b.cells = 8;
    for (int z = 0; z <= 8; ++z)
      for (int y = 0; y <= 8; ++y)
        for (int x = 0; x <= 8; ++x)
          b.values.push_back(whole.at(b.base.x() + x, b.base.y() + y, b.base.z() + z));
  }
  return blocks;
}

}  // namespace

TEST(CubeTable, EveryCrossingEdgeAndOnlyThoseCarryVertices) {
  for (int inside = 0; inside < 256; ++inside) {
    std::set<std::pair<int, int>> used;
    for (const auto& t : cubeTriangles(inside))
      for (const auto& e : t) used.insert({e.corner, e.axis});
    for (int c = 0; c < 8; ++c)
      for (int axis = 0; axis < 3; ++axis) {
        if (c & (1 << axis)) continue;
        const bool crossing = ((inside >> c) & 1) != ((inside >> (c | 1 << axis)) & 1);
        EXPECT_EQ(used.count({c, axis}) == 1, crossing) << "case " << inside;
      }
  }
}

TEST(MarchingCubes, SphereIsClosedWithCorrectVolume) {
  const double r = 11.3;
  FieldBlock block = sphereBlock(32, Eigen::Vector3d(16.2, 15.7, 16.4), r);
  VoxelGrid grid;
  MeshPiece piece;
  extractBlock(block, grid, piece);
  TriangleMesh mesh = mergePieces({piece});
  ASSERT_GT(mesh.faces.size(), 1000u);
  expectClosedOriented(mesh);
  const double exact = 4.0 / 3.0 * M_PI * r * r * r;
  EXPECT_NEAR(enclosedVolume(mesh) / exact, 1.0, 0.01);  // positive: normals point outward
}

TEST(MarchingCubes, JoinedPiecesAreThePieceOfAllTheirBlocks) {
  // Blocks (octants of a sphere) taken by one piece in order, against runs of them taken by
  // pieces of their own (as threads do) and joined: the same keys, positions and faces.
  const std::vector<FieldBlock> blocks =
      octants(sphereBlock(16, Eigen::Vector3d(8.3, 7.6, 8.1), 5.2));
  const VoxelGrid grid;
  MeshPiece one;
  for (const FieldBlock& b : blocks) extractBlock(b, grid, one);
  for (const std::vector<int>& ends : {std::vector<int>{8}, {3, 8}, {1, 2, 6, 8}, {0, 5, 8, 8}}) {
    std::vector<MeshPiece> pieces(ends.size());
    for (size_t k = 0, b = 0; k < ends.size(); ++k)
      for (; b < static_cast<size_t>(ends[k]); ++b) extractBlock(blocks[b], grid, pieces[k]);
    const MeshPiece joined = joinPieces(std::move(pieces));
    EXPECT_EQ(joined.keys, one.keys);
    EXPECT_EQ(joined.positions, one.positions);
    EXPECT_EQ(joined.faces, one.faces);
    ASSERT_EQ(joined.index.size(), one.index.size());
    for (size_t i = 0; i < one.keys.size(); ++i) EXPECT_EQ(joined.index.at(one.keys[i]), i);
  }
}

TEST(MarchingCubes, SplittingIntoPiecesGivesTheSameMesh) {
  const Eigen::Vector3d c(8.3, 7.6, 8.1);
  FieldBlock whole = sphereBlock(16, c, 5.2);
  VoxelGrid grid;
  MeshPiece one;
  extractBlock(whole, grid, one);
  // Octants of 8^3 cubes, in z-major order, reproduce the whole extraction's cube order
  // only up to permutation; compare as sets of triangles by vertex position.
  const std::vector<FieldBlock> blocks = octants(whole);
  std::vector<MeshPiece> pieces(8);
  for (int o = 0; o < 8; ++o) extractBlock(blocks[o], grid, pieces[o]);
  TriangleMesh a = mergePieces({one}), b = mergePieces(pieces);
  EXPECT_EQ(a.vertices.size(), b.vertices.size());  // no duplicates at the seams
  ASSERT_EQ(a.faces.size(), b.faces.size());
  expectClosedOriented(b);
  std::multiset<std::array<double, 9>> fa, fb;
  auto key = [](const TriangleMesh& m, const Triangle& t) {
    std::array<double, 9> k;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) k[3 * i + j] = m.vertices[t[i]][j];
    return k;
  };
  for (const auto& t : a.faces) fa.insert(key(a, t));
  for (const auto& t : b.faces) fb.insert(key(b, t));
  EXPECT_EQ(fa, fb);
}

TEST(MarchingCubes, UnobservedCornersProduceNoTriangles) {
  FieldBlock block = sphereBlock(16, Eigen::Vector3d(8, 8, 8), 5);
  for (int y = 0; y <= 16; ++y)
    for (int x = 0; x <= 16; ++x) block.values[(8 * 17 + y) * 17 + x] = NAN;  // plane z = 8
  MeshPiece piece;
  extractBlock(block, VoxelGrid{}, piece);
  for (const auto& p : piece.positions) EXPECT_TRUE(p.z() <= 7.0 || p.z() >= 9.0) << p.z();
}
