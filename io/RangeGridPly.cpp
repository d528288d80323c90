#include "rangefuse/io/RangeGridPly.h"

#include <charconv>
#include <cmath>

#include "PlainRangeGrid.h"
#include "PlyFile.h"
#include "VertexColours.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/Limits.h"

namespace rangefuse::io {
namespace {

using internal::PlyElementData;
using internal::PlyFile;

double infoNumber(const std::string& path, const std::map<std::string, std::string>& info,
                  const std::string& key, bool required) {
  auto it = info.find(key);
  if (it == info.end()) {
    if (required) throw InputError(path + ": header lacks 'obj_info " + key + "'");
    return std::nan("");
  }
  double v = 0;
  const std::string& s = it->second;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v))
    throw InputError(path + ": 'obj_info " + key + " " + s + "' is not a number");
  return v;
}

void readPoints(const PlyFile& f, RangeGrid& g) {
  const PlyElementData* v = f.find("vertex");
  if (!v) throw InputError(f.path + ": no 'vertex' element");
  int cx = v->scalarColumn("x"), cy = v->scalarColumn("y"), cz = v->scalarColumn("z");
  if (cx < 0 || cy < 0 || cz < 0) throw InputError(f.path + ": vertex lacks x, y or z");
  g.points.resize(v->element.count);
  for (uint64_t i = 0; i < v->element.count; ++i) {
    Eigen::Vector3d p(v->scalar(i, cx), v->scalar(i, cy), v->scalar(i, cz));
    if (!p.allFinite())
      throw InputError(f.path + ": vertex #" + std::to_string(i) + " has a NaN or Inf coordinate");
    g.points[i] = p;
  }
  g.colours = elementColours(f.path, *v, g.colourKind);
}

void readCells(const PlyFile& f, RangeGrid& g) {
  const PlyElementData* r = f.find("range_grid");
  if (!r) throw InputError(f.path + ": no 'range_grid' element");
  int li = r->listIndex("vertex_indices");
  if (li < 0) throw InputError(f.path + ": range_grid lacks list 'vertex_indices'");
  const uint64_t cells = static_cast<uint64_t>(g.cols) * g.rows;
  if (r->element.count != cells)
    throw InputError(f.path + ": range_grid has " + std::to_string(r->element.count) +
                     " cells but num_cols x num_rows = " + std::to_string(cells));
  const auto& off = r->listOffsets[li];
  const auto& val = r->listValues[li];
  g.cell.assign(cells, -1);
  for (uint64_t i = 0; i < cells; ++i) {
    uint32_t n = off[i + 1] - off[i];
    if (n > 1)
      throw InputError(f.path + ": range_grid cell #" + std::to_string(i) + " has " +
                       std::to_string(n) + " indices (0 or 1 allowed)");
    if (n == 0) continue;
    int64_t idx = val[off[i]];
    if (idx < 0 || idx >= static_cast<int64_t>(g.points.size()))
      throw InputError(f.path + ": range_grid cell #" + std::to_string(i) + ": vertex index " +
                       std::to_string(idx) + " out of range (" + std::to_string(g.points.size()) +
                       " vertices)");
    g.cell[i] = static_cast<int32_t>(idx);
  }
}

/// The grid's size and pinhole intrinsics, from the header's obj_info lines.
RangeGrid gridShape(const std::string& path, const std::map<std::string, std::string>& info,
                    const InputLimits& limits) {
  RangeGrid g;
  double cols = infoNumber(path, info, "num_cols", true);
  double rows = infoNumber(path, info, "num_rows", true);
  if (cols < 1 || rows < 1 || cols != std::floor(cols) || rows != std::floor(rows))
    throw InputError(path + ": bad grid size num_cols=" + std::to_string(cols) +
                     " num_rows=" + std::to_string(rows));
  checkLimit(path, "grid num_cols x num_rows =", cols * rows, limits.maxGridCells,
             "max-grid-cells");
  g.cols = static_cast<int>(cols);
  g.rows = static_cast<int>(rows);
  double fx = infoNumber(path, info, "pinhole_fx", false);
  if (!std::isnan(fx)) {
    g.pinhole = Pinhole{fx, infoNumber(path, info, "pinhole_fy", true),
                        infoNumber(path, info, "pinhole_cx", true),
                        infoNumber(path, info, "pinhole_cy", true)};
  }
  return g;
}

RangeGrid gridFrom(const std::string& name, std::string_view text, const InputLimits& limits) {
  const internal::PlyHeader h = internal::parsePlyHeader(name, text);
  internal::checkPlyCounts(name, h, text.size(), limits.maxElements);
  RangeGrid g = gridShape(name, h.objInfo, limits);
  // Little-endian binary grids (ours, most converters') decode in one pass; any other layout,
  // and any file with something wrong in its body, goes through the general reader, which
  // says what.
  if (!internal::decodePlainRangeGrid(h, text, g)) {
    const PlyFile f = internal::parsePly(name, text, limits.maxElements);
    readPoints(f, g);
    readCells(f, g);
  }
  return g;
}

}  // namespace

RangeGrid parseRangeGridPly(const std::string& name, const std::string& text,
                            const InputLimits& limits) {
  return gridFrom(name, text, limits);
}

RangeGrid readRangeGridPly(const std::string& path, const InputLimits& limits) {
  const internal::FileBytes bytes(path);
  return gridFrom(path, bytes.view(), limits);
}

}  // namespace rangefuse::io
