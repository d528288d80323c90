#include "PlainRangeGrid.h"

#include <cstdint>
#include <cstring>

namespace rangefuse::io::internal {
namespace {

constexpr size_t kNotPlain = SIZE_MAX;  // what an element reader returns for any other layout

/// Where a vertex's coordinates lie in its record.
struct VertexLayout {
  size_t stride = 0;
  size_t x = 0, y = 0, z = 0;
  PlyType type = PlyType::Float32;
};

bool vertexLayout(const PlyElement& e, VertexLayout& v) {
  int found = 0;
  for (const PlyProperty& p : e.properties) {
    if (p.isList) return false;
    // Colour or intensity: the general reader keeps it.
    if (p.name == "red" || p.name == "diffuse_red" || p.name == "intensity") return false;
    size_t* at = p.name == "x" ? &v.x : p.name == "y" ? &v.y : p.name == "z" ? &v.z : nullptr;
    if (at) {
      const bool floating = p.type == PlyType::Float32 || p.type == PlyType::Float64;
      if (!floating || (found > 0 && p.type != v.type)) return false;
      v.type = p.type;
      *at = v.stride;
      ++found;
    }
    v.stride += typeSize(p.type);
  }
  return found == 3;  // a name given twice is left to the general reader
}

template <class T>
bool decodePoints(const char* at, const VertexLayout& v, std::vector<Eigen::Vector3d>& points) {
  for (Eigen::Vector3d& p : points) {
    T x, y, z;
    std::memcpy(&x, at + v.x, sizeof(T));
    std::memcpy(&y, at + v.y, sizeof(T));
    std::memcpy(&z, at + v.z, sizeof(T));
    p = Eigen::Vector3d(x, y, z);
    if (!p.allFinite()) return false;
    at += v.stride;
  }
  return true;
}

/// The bytes the vertex element takes, or kNotPlain if it is another layout or a point is not
/// finite.
size_t readPoints(const PlyElement& e, std::string_view body, RangeGrid& g) {
  VertexLayout v;
  if (!vertexLayout(e, v) || body.size() / v.stride < e.count) return kNotPlain;
  g.points.resize(e.count);
  const bool ok = v.type == PlyType::Float32 ? decodePoints<float>(body.data(), v, g.points)
                                             : decodePoints<double>(body.data(), v, g.points);
  return ok ? v.stride * e.count : kNotPlain;
}

/// The bytes the range_grid element takes, or kNotPlain if it is another layout or a cell is not
/// 0 or 1 index of a point (the points' count is the vertex element's).
size_t readCells(const PlyElement& e, uint64_t points, std::string_view body, RangeGrid& g) {
  if (e.properties.size() != 1) return kNotPlain;
  const PlyProperty& p = e.properties[0];
  const bool isSigned = p.type == PlyType::Int32;
  if (!p.isList || p.countType != PlyType::UInt8 || (!isSigned && p.type != PlyType::UInt32))
    return kNotPlain;
  if (e.count != static_cast<uint64_t>(g.cols) * g.rows || body.size() < e.count) return kNotPlain;
  const unsigned char* const first = reinterpret_cast<const unsigned char*>(body.data());
  const unsigned char *at = first, *end = first + body.size();
  g.cell.assign(e.count, -1);
  for (int32_t& cell : g.cell) {
    if (at == end) return kNotPlain;
    const unsigned n = *at++;
    if (n == 0) continue;
    if (n != 1 || end - at < 4) return kNotPlain;
    int32_t s;
    uint32_t u;
    std::memcpy(&s, at, 4);
    std::memcpy(&u, at, 4);
    const int64_t index = isSigned ? static_cast<int64_t>(s) : static_cast<int64_t>(u);
    if (index < 0 || static_cast<uint64_t>(index) >= points) return kNotPlain;
    cell = static_cast<int32_t>(index);
    at += 4;
  }
  return static_cast<size_t>(at - first);
}

bool decodeBody(const PlyHeader& h, std::string_view text, RangeGrid& g) {
  const PlyElement* vertex = nullptr;
  for (const PlyElement& e : h.elements)
    if (e.name == "vertex") vertex = &e;
  if (!vertex || h.elements.size() != 2) return false;
  size_t at = h.bodyOffset;
  for (const PlyElement& e : h.elements) {
    const std::string_view body = text.substr(at);
    const size_t bytes = &e == vertex             ? readPoints(e, body, g)
                         : e.name == "range_grid" ? readCells(e, vertex->count, body, g)
                                                  : kNotPlain;
    if (bytes == kNotPlain) return false;
    at += bytes;
  }
  return at == text.size();  // bytes after the last element: the general reader says so
}

}  // namespace

bool decodePlainRangeGrid(const PlyHeader& h, std::string_view text, RangeGrid& g) {
  const uint16_t one = 1;
  const bool littleHost = *reinterpret_cast<const unsigned char*>(&one) == 1;
  if (h.format == PlyFormat::BinaryLittleEndian && littleHost && decodeBody(h, text, g))
    return true;
  g.points.clear();
  g.cell.clear();
  return false;
}

}  // namespace rangefuse::io::internal
