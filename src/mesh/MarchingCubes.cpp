#include "rangefuse/mesh/MarchingCubes.h"

#include <cmath>

namespace rangefuse {
namespace {

int32_t vertexFor(const FieldBlock& block, const VoxelGrid& grid, const VoxelIndex& cell,
                  const CubeEdge& e, MeshPiece& piece) {
  const VoxelIndex local =
      cell + VoxelIndex((e.corner >> 0) & 1, (e.corner >> 1) & 1, (e.corner >> 2) & 1);
  const VoxelIndex v = block.base + local;
  const uint64_t key = edgeKey(v, e.axis);
  const auto [at, isNew] = piece.index.emplace(key, static_cast<int32_t>(piece.keys.size()));
  if (!isNew) return at;
  VoxelIndex lo = local, hi = local;
  hi[e.axis] += 1;
  const double d0 = block.at(lo.x(), lo.y(), lo.z()), d1 = block.at(hi.x(), hi.y(), hi.z());
  const double t = d0 / (d0 - d1);
  Eigen::Vector3d p = grid.centre(v);
  p[e.axis] += grid.voxel * t;
  piece.keys.push_back(key);
  piece.positions.push_back(p);
  const size_t side = block.side();
  const auto index = [&](const VoxelIndex& l) {
    return (static_cast<size_t>(l.z()) * side + l.y()) * side + l.x();
  };
  if (!block.filled.empty())
    piece.filled.push_back(block.filled[index(lo)] | block.filled[index(hi)]);
  if (!block.colours.empty()) {  // the colour along the edge, as the position
    const Eigen::Vector3f &c0 = block.colours[index(lo)], &c1 = block.colours[index(hi)];
    piece.colours.push_back(c0 + static_cast<float>(t) * (c1 - c0));
  }
  return at;
}

}  // namespace

uint64_t edgeKey(const VoxelIndex& v, int axis) {
  return (static_cast<uint64_t>(v.z()) << 42) | (static_cast<uint64_t>(v.y()) << 22) |
         (static_cast<uint64_t>(v.x()) << 2) | static_cast<uint64_t>(axis);
}

void extractBlock(const FieldBlock& block, const VoxelGrid& grid, MeshPiece& piece) {
  VoxelIndex cell;
  for (cell.z() = 0; cell.z() < block.cells; ++cell.z())
    for (cell.y() = 0; cell.y() < block.cells; ++cell.y())
      for (cell.x() = 0; cell.x() < block.cells; ++cell.x()) {
        int inside = 0;
        bool observed = true;
        for (int c = 0; c < 8 && observed; ++c) {
          float d = block.at(cell.x() + (c & 1), cell.y() + ((c >> 1) & 1), cell.z() + (c >> 2));
          observed = !std::isnan(d);
          if (d < 0) inside |= 1 << c;
        }
        if (!observed || inside == 0 || inside == 255) continue;
        for (const CubeTriangle& t : cubeTriangles(inside)) {
          Triangle f;
          for (int k = 0; k < 3; ++k) f[k] = vertexFor(block, grid, cell, t[k], piece);
          piece.faces.push_back(f);
        }
      }
}

MeshPiece joinPieces(std::vector<MeshPiece> pieces) {
  if (pieces.empty()) return {};
  MeshPiece all = std::move(pieces.front());
  size_t keys = 0;
  for (const MeshPiece& p : pieces) keys += p.keys.size();
  all.index.reserve(keys);
  for (size_t j = 1; j < pieces.size(); ++j) {
    const MeshPiece& p = pieces[j];
    // A piece numbers its vertices by first use, so its new ones come in the order they would
    // have been met had the cubes before it been in the same piece.
    std::vector<int32_t> to(p.keys.size());
    for (size_t i = 0; i < p.keys.size(); ++i) {
      const auto [at, isNew] = all.index.emplace(p.keys[i], static_cast<int32_t>(all.keys.size()));
      if (isNew) {
        all.keys.push_back(p.keys[i]);
        all.positions.push_back(p.positions[i]);
        if (!p.colours.empty()) all.colours.push_back(p.colours[i]);
        if (!p.filled.empty()) all.filled.push_back(p.filled[i]);
      }
      to[i] = at;
    }
    for (const Triangle& f : p.faces) all.faces.push_back({to[f[0]], to[f[1]], to[f[2]]});
  }
  return all;
}

TriangleMesh mergePieces(const std::vector<MeshPiece>& pieces) {
  TriangleMesh mesh;
  std::unordered_map<uint64_t, int32_t> global;
  for (const MeshPiece& piece : pieces)
    for (const Triangle& t : piece.faces) {
      Triangle g;
      for (int k = 0; k < 3; ++k) {
        auto [it, isNew] =
            global.emplace(piece.keys[t[k]], static_cast<int32_t>(mesh.vertices.size()));
        if (isNew) {
          mesh.vertices.push_back(piece.positions[t[k]]);
          if (!piece.colours.empty()) mesh.colours.push_back(piece.colours[t[k]]);
          if (!piece.filled.empty()) mesh.filled.push_back(piece.filled[t[k]]);
        }
        g[k] = it->second;
      }
      mesh.faces.push_back(g);
    }
  return mesh;
}

std::vector<Eigen::Vector3d> vertexNormals(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> n(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (const Triangle& t : mesh.faces) {
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    Eigen::Vector3d fn = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n[t[k]] += fn;
  }
  for (auto& v : n)
    if (v.norm() > 0) v.normalize();
  return n;
}

}  // namespace rangefuse
