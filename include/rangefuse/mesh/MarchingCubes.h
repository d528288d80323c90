// Marching cubes over blocks of voxel values, with vertices named by global lattice edge.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "rangefuse/core/TriangleMesh.h"
#include "rangefuse/mesh/EdgeIndex.h"
#include "rangefuse/volume/VoxelGrid.h"

namespace rangefuse {

/// A cube edge: from corner `corner` (bit 0 = +x, bit 1 = +y, bit 2 = +z) along `axis`.
struct CubeEdge {
  int corner;
  int axis;
};
using CubeTriangle = std::array<CubeEdge, 3>;

/// Triangles for a cube whose corners with bit c set in `inside` have negative values.
/// Normals (right-hand rule) point toward positive values. Faces with two diagonal
/// inside corners always separate them, so neighbouring cubes agree and meshes close.
const std::vector<CubeTriangle>& cubeTriangles(int inside);

/// Voxel values on an (cells+1)^3 lattice starting at voxel `base`; NaN = unobserved.
struct FieldBlock {
  VoxelIndex base;
  int cells = 0;
  std::vector<float> values;
  std::vector<Eigen::Vector3f> colours;  ///< empty, or one per value
  /// Empty, or one per value: 1 where the value was carved, not observed (HoleFill).
  std::vector<uint8_t> filled;

  int side() const { return cells + 1; }
  float at(int x, int y, int z) const {
    return values[(static_cast<size_t>(z) * side() + y) * side() + x];
  }
};

/// Global name of the lattice edge from voxel v along axis (20 bits per axis).
uint64_t edgeKey(const VoxelIndex& v, int axis);

/// Triangles with vertices named by edge key, deduplicated within the piece.
struct MeshPiece {
  std::vector<uint64_t> keys;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3f> colours;  ///< empty, or one per position
  std::vector<uint8_t> filled;           ///< empty, or one per position: an end was carved
  std::vector<Triangle> faces;           ///< indices into keys/positions
  EdgeIndex index;
};

/// Adds the triangles of every cube of the block that has all eight corners observed.
void extractBlock(const FieldBlock& block, const VoxelGrid& grid, MeshPiece& piece);

/// Joins pieces given in cube order into the piece extractBlock would have made of all their
/// cubes: the same vertices, numbered in order of first use, and the same faces.
MeshPiece joinPieces(std::vector<MeshPiece> pieces);

/// Joins pieces given in global cube order into one mesh; vertices are numbered in order
/// of first use, so the result does not depend on how the cubes were split into pieces.
TriangleMesh mergePieces(const std::vector<MeshPiece>& pieces);

/// Area-weighted vertex normals.
std::vector<Eigen::Vector3d> vertexNormals(const TriangleMesh& mesh);

}  // namespace rangefuse
