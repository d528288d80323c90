#include <algorithm>

#include "rangefuse/mesh/MarchingCubes.h"

namespace rangefuse {
namespace {

/// The four corners of a cube face in counter-clockwise order seen from outside.
std::array<int, 4> faceCorners(int axis, int side) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  auto corner = [&](int bu, int bv) { return (side << axis) | (bu << u) | (bv << v); };
  std::array<int, 4> f = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
  if (side == 0) std::reverse(f.begin(), f.end());  // (u, v, axis) is right-handed
  return f;
}

CubeEdge edgeBetween(int a, int b) {
  int axis = 0;
  while (((a ^ b) >> axis) != 1) ++axis;
  return CubeEdge{std::min(a, b), axis};
}

int edgeId(const CubeEdge& e) {
  return e.corner * 3 + e.axis;
}

/// Walks each face's crossing edges into closed loops and fans them into triangles.
std::vector<CubeTriangle> buildCase(int inside) {
  auto in = [&](int c) { return (inside >> c) & 1; };
  int next[24];
  std::fill(std::begin(next), std::end(next), -1);
  CubeEdge edges[24];
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      auto f = faceCorners(axis, side);
      for (int k = 0; k < 4; ++k) {
        if (in(f[k]) || !in(f[(k + 1) % 4])) continue;  // edge k enters the inside region
        int m = (k + 1) % 4;
        while (in(f[(m + 1) % 4])) m = (m + 1) % 4;  // first edge leaving it again
        CubeEdge from = edgeBetween(f[k], f[(k + 1) % 4]);
        CubeEdge to = edgeBetween(f[m], f[(m + 1) % 4]);
        next[edgeId(from)] = edgeId(to);
        edges[edgeId(from)] = from;
        edges[edgeId(to)] = to;
      }
    }
  std::vector<CubeTriangle> tris;
  bool used[24] = {};
  for (int s = 0; s < 24; ++s) {
    if (next[s] < 0 || used[s]) continue;
    std::vector<int> loop;
    for (int e = s; !used[e]; e = next[e]) {
      used[e] = true;
      loop.push_back(e);
    }
    for (size_t i = 1; i + 1 < loop.size(); ++i)
      tris.push_back({edges[loop[0]], edges[loop[i]], edges[loop[i + 1]]});
  }
  return tris;
}

}  // namespace

const std::vector<CubeTriangle>& cubeTriangles(int inside) {
  static const std::vector<std::vector<CubeTriangle>> table = [] {
    std::vector<std::vector<CubeTriangle>> t(256);
    for (int c = 0; c < 256; ++c) t[c] = buildCase(c);
    return t;
  }();
  return table[inside];
}

}  // namespace rangefuse
