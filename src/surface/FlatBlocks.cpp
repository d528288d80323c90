#include "rangefuse/surface/FlatBlocks.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "GridShape.h"

namespace rangefuse {
namespace {

/// The blocks of 2 x 2 cells of a grid and which of them are joined.
struct Blocks {
  int rows = 0, cols = 0;  ///< whole blocks down and across
  std::vector<uint8_t> flat;
  bool joined(int b, int c) const {
    return b >= 0 && c >= 0 && b < rows && c < cols && flat[size_t(b) * cols + c];
  }
};

/// The grid's cell (row, column) of each triangle: its corners' least row and column (the grid
/// does not close a turn), and in `kept` per cell bit 1 for its upper triangle (two corners on
/// the cell's first row) and bit 2 for its lower one.
std::vector<std::array<int32_t, 2>> triangleCells(const RangeGrid& g, const GridSurface& s,
                                                  std::vector<uint8_t>& kept) {
  std::vector<std::array<int32_t, 2>> place(g.points.size());
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c)
      if (const int32_t i = g.at(r, c); i >= 0) place[i] = {r, c};
  kept.assign(size_t(g.rows) * g.cols, 0);
  std::vector<std::array<int32_t, 2>> cells;
  cells.reserve(s.mesh.faces.size());
  for (const Triangle& t : s.mesh.faces) {
    std::array<int32_t, 2> cell = place[s.sources[t[0]]];
    int onFirstRow = 0;
    for (int32_t v : t)
      cell = {std::min(cell[0], place[s.sources[v]][0]), std::min(cell[1], place[s.sources[v]][1])};
    for (int32_t v : t) onFirstRow += place[s.sources[v]][0] == cell[0];
    kept[size_t(cell[0]) * g.cols + cell[1]] |= onFirstRow == 2 ? 1 : 2;
    cells.push_back(cell);
  }
  return cells;
}

/// Joins blocks of 2 x 2 cells: the state shared by the flatness test and the new triangles.
class Joiner {
 public:
  Joiner(const RangeGrid& g, const GridTriangulation& rules, double tolerance, const GridSurface& s)
      : g_(g), rules_(rules), tolerance_(tolerance), s_(s), vertexOf_(g.points.size(), -1) {
    for (size_t v = 0; v < s.sources.size(); ++v) vertexOf_[s.sources[v]] = int32_t(v);
  }

  /// Which blocks are flat, from which cells kept both triangles (`kept`, triangleCells).
  Blocks findFlat(const std::vector<uint8_t>& kept) const {
    Blocks b;
    b.rows = (g_.rows - 1) / 2, b.cols = (g_.cols - 1) / 2;
    b.flat.assign(size_t(b.rows) * b.cols, 0);
    for (int i = 0; i < b.rows; ++i)
      for (int j = 0; j < b.cols; ++j) b.flat[size_t(i) * b.cols + j] = isFlat(kept, 2 * i, 2 * j);
    return b;
  }

  /// Block (r0, c0)'s triangles between its corners, with the middle of each side whose
  /// neighbour keeps its cells fine.
  void join(const Blocks& b, int r0, int c0, std::vector<Triangle>& out) const {
    const int i = r0 / 2, j = c0 / 2;
    // A side needs its middle vertex when cells lie beyond it that are not joined.
    const bool top = r0 > 0 && !b.joined(i - 1, j);
    const bool right = c0 + 2 < g_.cols - 1 && !b.joined(i, j + 1);
    const bool bottom = r0 + 2 < g_.rows - 1 && !b.joined(i + 1, j);
    const bool left = c0 > 0 && !b.joined(i, j - 1);
    const int32_t a = at(r0, c0), bb = at(r0, c0 + 2), c = at(r0 + 2, c0), d = at(r0 + 2, c0 + 2);
    if (!(top || right || bottom || left)) {
      emit(a, bb, c, out);
      emit(bb, d, c, out);
      return;
    }
    // A fan about the centre over the block's outline, wound as the cells' triangles are.
    std::array<int32_t, 8> loop;
    int n = 0;
    loop[n++] = a;
    if (top) loop[n++] = at(r0, c0 + 1);
    loop[n++] = bb;
    if (right) loop[n++] = at(r0 + 1, c0 + 2);
    loop[n++] = d;
    if (bottom) loop[n++] = at(r0 + 2, c0 + 1);
    loop[n++] = c;
    if (left) loop[n++] = at(r0 + 1, c0);
    const int32_t centre = at(r0 + 1, c0 + 1);
    for (int k = 0; k < n; ++k) emit(loop[k], loop[(k + 1) % n], centre, out);
  }

 private:
  /// The surface's vertex at grid cell (r, c); the caller knows one is there.
  int32_t at(int r, int c) const { return vertexOf_[g_.at(r, c)]; }

  void emit(int32_t a, int32_t b, int32_t c, std::vector<Triangle>& out) const {
    out.push_back(rules_.forward ? Triangle{a, b, c} : Triangle{a, c, b});
  }

  /// Block (r0, c0) is joined when its cells kept both their triangles (so its nine corners
  /// are vertices), its chords stay within the tolerance, and the triangulation would keep the
  /// joined triangles.
  bool isFlat(const std::vector<uint8_t>& kept, int r0, int c0) const {
    for (int r = r0; r < r0 + 2; ++r)
      for (int c = c0; c < c0 + 2; ++c)
        if (kept[size_t(r) * g_.cols + c] != 3) return false;
    Eigen::Vector3d down, across;
    turns(r0, c0, down, across);
    const Eigen::Vector3d &a = point(r0, c0), &b = point(r0, c0 + 2), &c = point(r0 + 2, c0),
                          &d = point(r0 + 2, c0 + 2);
    // Along a diagonal of length L the normal turns by t; its chord stands L t / 8 off the arc.
    const double turnAD = (down + across).norm(), turnBC = (down - across).norm();
    if (std::max((a - d).norm() * turnAD, (b - c).norm() * turnBC) / 8 > tolerance_) return false;
    return keeps(a, b, c) && keeps(b, d, c);
  }

  /// How the normals turn over the block's two rows (`down`) and two columns (`across`): the
  /// mean change from the first to the last row (column) of the 5 x 5 vertices about the block,
  /// or of its own 3 x 3 where the grid ends or has a gap. Means over rows average the noise of
  /// the filtered normals, which their spread alone would take for curvature.
  void turns(int r0, int c0, Eigen::Vector3d& down, Eigen::Vector3d& across) const {
    const int e = hasVertices(r0 - 1, c0 - 1, 5) ? 1 : 0;
    down.setZero(), across.setZero();
    for (int k = -e; k < 3 + e; ++k) {
      down += normal(r0 + 2 + e, c0 + k) - normal(r0 - e, c0 + k);
      across += normal(r0 + k, c0 + 2 + e) - normal(r0 + k, c0 - e);
    }
    const double perBlock = 1.0 / ((3 + 2 * e) * (1 + e));  // a mean, over 2 + 2e rows to 2
    down *= perBlock, across *= perBlock;
  }

  /// Whether every grid point of the n x n square from (r0, c0) is a vertex of the surface.
  bool hasVertices(int r0, int c0, int n) const {
    if (r0 < 0 || c0 < 0 || r0 + n > g_.rows || c0 + n > g_.cols) return false;
    for (int r = r0; r < r0 + n; ++r)
      for (int c = c0; c < c0 + n; ++c)
        if (const int32_t i = g_.at(r, c); i < 0 || vertexOf_[i] < 0) return false;
    return true;
  }

  /// Whether the triangulation's tests keep joined triangle a, b, c, as it is wound.
  bool keeps(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) const {
    const double maxEdge = 2 * rules_.maxEdge, minCos = rules_.minCosine;
    return rules_.forward ? internal::keepsTriangle(g_, a, b, c, maxEdge, minCos)
                          : internal::keepsTriangle(g_, a, c, b, maxEdge, minCos);
  }

  const Eigen::Vector3d& point(int r, int c) const { return s_.mesh.vertices[at(r, c)]; }
  const Eigen::Vector3d& normal(int r, int c) const { return s_.normals[at(r, c)]; }

  const RangeGrid& g_;
  const GridTriangulation& rules_;
  double tolerance_;
  const GridSurface& s_;
  std::vector<int32_t> vertexOf_;  ///< grid point to surface vertex, -1 if unused
};

}  // namespace

void joinFlatBlocks(const RangeGrid& grid, const GridTriangulation& rules, double tolerance,
                    GridSurface& surface) {
  if (!(tolerance > 0) || rules.wraps || surface.mesh.faces.empty()) return;
  std::vector<uint8_t> kept;
  const std::vector<std::array<int32_t, 2>> cells = triangleCells(grid, surface, kept);
  const Joiner joiner(grid, rules, tolerance, surface);
  const Blocks blocks = joiner.findFlat(kept);
  std::vector<Triangle> faces;
  faces.reserve(surface.mesh.faces.size());
  for (size_t f = 0; f < cells.size(); ++f) {
    const auto [r, c] = cells[f];
    if (!blocks.joined(r / 2, c / 2)) {
      faces.push_back(surface.mesh.faces[f]);
      continue;
    }
    // A joined block's triangles stand where its first cell's upper triangle stood.
    const bool first = r % 2 == 0 && c % 2 == 0 && (f == 0 || cells[f - 1] != cells[f]);
    if (first) joiner.join(blocks, r, c, faces);
  }
  surface.mesh.faces = std::move(faces);
}

}  // namespace rangefuse
