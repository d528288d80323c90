#include "PartPacking.h"

#include <cmath>
#include <cstring>
#include <numeric>

#include "ColourPacking.h"
#include "CompactAttributes.h"
#include "LimitPacking.h"
#include "PickedBytes.h"
#include "TrianglePacking.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {
namespace {

/// Appends the listed elements of v as packVector would append the vector made of them.
template <class T>
void packPicked(std::vector<char>& buf, const std::vector<T>& v, const std::vector<uint32_t>& pick,
                size_t per = 1) {
  const uint64_t n = v.empty() ? 0 : pick.size() * per;
  mpi::pack(buf, &n, 1);
  if (n > 0) appendPicked(buf, v, pick, per);
}

template <class T>
void packVector(std::vector<char>& buf, const std::vector<T>& v) {
  const uint64_t n = v.size();
  mpi::pack(buf, &n, 1);
  mpi::pack(buf, v.data(), n);
}

template <class T>
void unpackVector(const std::vector<char>& buf, size_t& pos, std::vector<T>& v) {
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  v.resize(n);
  mpi::unpack(buf, pos, v.data(), n);
}

/// Appends the count and each listed element's code, `Code` bits (a compact scan's normals
/// and confidences: their values are their codes' already).
template <class Code, class T, class Encode>
void packPickedCodes(std::vector<char>& buf, const std::vector<T>& v,
                     const std::vector<uint32_t>& pick, Encode encode) {
  const uint64_t n = v.empty() ? 0 : pick.size();
  mpi::pack(buf, &n, 1);
  char* out = grow(buf, n * sizeof(Code));
  for (size_t k = 0; k < n; ++k) {
    const Code c = encode(v[pick[k]]);
    std::memcpy(out, &c, sizeof c), out += sizeof c;
  }
}

template <class Code, class T, class Decode>
void unpackCodes(const std::vector<char>& buf, size_t& pos, std::vector<T>& v, Decode decode) {
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  v.resize(n);
  const char* in = buf.data() + pos;
  for (T& x : v) {
    Code c;
    std::memcpy(&c, in, sizeof c), in += sizeof c;
    x = decode(c);
  }
  pos += n * sizeof(Code);
}

/// Appends the listed normals and confidences: a compact scan's as their codes.
void packPickedAttributes(std::vector<char>& buf, const PrismScan& scan,
                          const std::vector<uint32_t>& pick) {
  const ScanSurface& s = scan.surface;
  if (!scan.compact()) {
    packPicked(buf, s.normals, pick);
    return packPicked(buf, s.confidence, pick);
  }
  packPickedCodes<uint32_t>(buf, s.normals, pick, [](const auto& n) { return normalCode(n); });
  packPickedCodes<uint16_t>(buf, s.confidence, pick, [](double c) { return confidenceCode(c); });
}

void unpackAttributes(const std::vector<char>& buf, size_t& pos, PrismScan& s) {
  if (!s.compact()) {
    unpackVector(buf, pos, s.surface.normals);
    return unpackVector(buf, pos, s.surface.confidence);
  }
  unpackCodes<uint32_t>(buf, pos, s.surface.normals, [](uint32_t c) { return normalOf(c); });
  unpackCodes<uint16_t>(buf, pos, s.surface.confidence, [](uint16_t c) { return confidenceOf(c); });
}

/// Appends the listed points; a compact scan's as its lattice's origin, the count, the bytes
/// an offset takes (3 when every one fits 24 bits, else 4) and the offsets.
void packPickedPoints(std::vector<char>& buf, const PrismScan& scan,
                      const std::vector<uint32_t>& pick) {
  if (!scan.compact()) return packPicked(buf, scan.surface.points, pick);
  mpi::pack(buf, scan.origin.data(), 3);
  const uint64_t n = pick.size();
  mpi::pack(buf, &n, 1);
  std::vector<int32_t> offsets(3 * n);
  const double perQuantum = 1 / scan.quantum;  // a power of two: exact
  int32_t most = 0;
  for (size_t k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) {
      // Exact, no rounding: a compact scan's points are whole quanta from its origin.
      const auto o =
          static_cast<int32_t>((scan.surface.points[pick[k]][c] - scan.origin[c]) * perQuantum);
      offsets[3 * k + c] = o;
      most = std::max(most, o < 0 ? -(o + 1) : o);  // the bits o takes beside its sign
    }
  const uint8_t width = most < (1 << 23) ? 3 : 4;
  mpi::pack(buf, &width, 1);
  char* out = grow(buf, offsets.size() * width);
  for (const int32_t o : offsets)
    for (int b = 0; b < width; ++b) *out++ = static_cast<char>(static_cast<uint32_t>(o) >> 8 * b);
}

void unpackPoints(const std::vector<char>& buf, size_t& pos, PrismScan& s) {
  if (!s.compact()) return unpackVector(buf, pos, s.surface.points);
  mpi::unpack(buf, pos, s.origin.data(), 3);
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  uint8_t width;
  mpi::unpack(buf, pos, &width, 1);
  s.surface.points.resize(n);
  const char* in = buf.data() + pos;
  const int shift = 8 * (4 - width);  // moves a 24-bit offset's sign to bit 31 and back
  for (Eigen::Vector3d& p : s.surface.points)
    for (int c = 0; c < 3; ++c) {
      uint32_t bits = 0;
      for (int b = 0; b < width; ++b) bits |= uint32_t(static_cast<uint8_t>(*in++)) << 8 * b;
      const auto k = static_cast<int32_t>(bits << shift) >> shift;
      p[c] = s.origin[c] + k * s.quantum;
    }
  pos += n * 3 * width;
}

/// Moves pos past a vector of elements of `bytes` each.
void skipVector(const std::vector<char>& buf, size_t& pos, size_t bytes) {
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  pos += n * bytes;
}

/// Appends texels: the first row, then each row's first column, where each row starts and the
/// cells, as vectors.
void packTexels(std::vector<char>& buf, const TexelImage& part) {
  mpi::pack(buf, &part.top, 1);
  packVector(buf, part.left);
  packVector(buf, part.from);
  packTexelCells(buf, part.cells);
}

void unpackTexels(const std::vector<char>& buf, size_t& pos, TexelImage& t) {
  mpi::unpack(buf, pos, &t.top, 1);
  unpackVector(buf, pos, t.left);
  unpackVector(buf, pos, t.from);
  unpackTexelCells(buf, pos, t.cells);
}

}  // namespace

std::vector<uint32_t> usedVertices(const ScanSurface& s, const std::vector<uint32_t>& triangles,
                                   std::vector<int32_t>& remap) {
  std::vector<uint32_t> used;
  for (uint32_t t : triangles)
    for (const int32_t v : s.triangles[t])
      if (remap[v] < 0) {
        remap[v] = static_cast<int32_t>(used.size());
        used.push_back(v);
      }
  return used;
}

void packPart(std::vector<char>& buf, uint64_t index, const PrismScan& scan,
              const std::vector<uint32_t>& triangles, std::vector<int32_t>& remap) {
  const ScanSurface& s = scan.surface;
  const std::vector<uint32_t> used = usedVertices(s, triangles, remap);
  // The texels the part's triangles need.
  const TexelImage texels =
      s.texels.empty() ? TexelImage{}
                       : triangleTexels(s.texels, s.blocks, s.triangles, s.texelSide, &triangles);
  const size_t v = used.size(), t = triangles.size();
  const size_t real = scan.compact() ? sizeof(float) : sizeof(double);
  // A vertex's normal and confidence: codes (CompactAttributes.h) or four doubles.
  const size_t attributes =
      scan.compact() ? sizeof(uint32_t) + sizeof(uint16_t) : 4 * sizeof(double);
  // About the bytes: at most, unless a corner needs 32 bits or more than one prism in 16
  // has a truncated limit.
  const size_t bytes = 16 * sizeof(uint64_t) + 3 + sizeof(s.texelSide) + sizeof(int32_t) +
                       sizeof(s.sensor) + v * (3 * real + attributes) + t * 3 * sizeof(uint16_t) +
                       2 * real + t / 4 + t * 2 * real / 16 +
                       (s.colours.empty() ? 0 : v * sizeof(Colour)) +
                       texels.cells.size() * sizeof(Texel) + size_t(texels.rows()) * 8 + 4 +
                       (s.blocks.empty() ? 0 : v * sizeof(s.blocks[0]));
  buf.reserve(buf.size() + bytes);
  mpi::pack(buf, &index, 1);
  mpi::pack(buf, &scan.quantum, 1);
  packPickedPoints(buf, scan, used);
  packPickedAttributes(buf, scan, used);
  packTriangles(buf, s.triangles, triangles, remap);
  packColours(buf, s.colours, used);
  mpi::pack(buf, &s.texelSide, 1);
  packTexels(buf, texels);
  packBlocks(buf, s.blocks, used);
  packLimits(buf, scan.limits, triangles, scan.compact());
  mpi::pack(buf, &s.sensor, 1);
  for (uint32_t k : used) remap[k] = -1;
}

void packWhole(std::vector<char>& buf, uint64_t index, const PrismScan& scan) {
  std::vector<uint32_t> all(scan.surface.triangles.size());
  std::iota(all.begin(), all.end(), 0u);
  std::vector<int32_t> remap(scan.surface.points.size(), -1);
  packPart(buf, index, scan, all, remap);
}

uint64_t unpackPart(const std::vector<char>& buf, size_t& pos, PrismScan& s) {
  uint64_t index;
  mpi::unpack(buf, pos, &index, 1);
  mpi::unpack(buf, pos, &s.quantum, 1);
  unpackPoints(buf, pos, s);
  unpackAttributes(buf, pos, s);
  unpackTriangles(buf, pos, s.surface.triangles);
  unpackColours(buf, pos, s.surface.colours);
  mpi::unpack(buf, pos, &s.surface.texelSide, 1);
  unpackTexels(buf, pos, s.surface.texels);
  unpackBlocks(buf, pos, s.surface.blocks);
  unpackLimits(buf, pos, s.limits, s.compact());
  mpi::unpack(buf, pos, &s.surface.sensor, 1);
  return index;
}

uint64_t skipPart(const std::vector<char>& buf, size_t& pos) {
  const ScanSurface s;
  uint64_t index;
  mpi::unpack(buf, pos, &index, 1);
  double quantum;
  mpi::unpack(buf, pos, &quantum, 1);
  if (quantum > 0) pos += 3 * sizeof(double);  // the lattice's origin
  if (quantum > 0) {  // points: their count, the bytes an offset takes and the offsets
    uint64_t n;
    mpi::unpack(buf, pos, &n, 1);
    uint8_t width;
    mpi::unpack(buf, pos, &width, 1);
    pos += n * 3 * width;
  } else {
    skipVector(buf, pos, 3 * sizeof(double));
  }
  skipVector(buf, pos, quantum > 0 ? sizeof(uint32_t) : 3 * sizeof(double));  // normals
  skipVector(buf, pos, quantum > 0 ? sizeof(uint16_t) : sizeof(double));      // confidences
  skipTriangles(buf, pos);
  skipColours(buf, pos);
  pos += sizeof(s.texelSide);
  pos += sizeof(int32_t);                  // the texels' first row
  skipVector(buf, pos, sizeof(int32_t));   // each row's first column
  skipVector(buf, pos, sizeof(uint32_t));  // where each row starts
  skipTexelCells(buf, pos);
  skipBlocks(buf, pos);
  skipLimits(buf, pos, quantum > 0);
  pos += sizeof(s.sensor);
  return index;
}

}  // namespace rangefuse::internal
