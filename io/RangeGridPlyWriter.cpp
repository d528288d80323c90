#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>

#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/RangeGridPly.h"

namespace rangefuse::io {
namespace {

template <class T>
void putBinary(std::ostream& out, T v, bool bigEndian) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (bigEndian) std::reverse(b, b + sizeof(T));
  out.write(b, sizeof(T));
}

void writeHeader(std::ostream& out, const RangeGrid& g, PlyEncoding e) {
  static const char* kFormat[] = {"ascii", "binary_little_endian", "binary_big_endian"};
  out << "ply\nformat " << kFormat[static_cast<int>(e)] << " 1.0\n"
      << "obj_info num_cols " << g.cols << "\nobj_info num_rows " << g.rows << "\n";
  if (g.pinhole) {
    out << std::setprecision(17) << "obj_info pinhole_fx " << g.pinhole->fx
        << "\nobj_info pinhole_fy " << g.pinhole->fy << "\nobj_info pinhole_cx " << g.pinhole->cx
        << "\nobj_info pinhole_cy " << g.pinhole->cy << "\n";
  }
  out << "element vertex " << g.points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (g.colourKind == ColourKind::rgb)
    out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (g.colourKind == ColourKind::intensity) out << "property float intensity\n";
  out << "element range_grid " << g.cell.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
}

}  // namespace

void writeRangeGridPly(const std::string& path, const RangeGrid& g, PlyEncoding e) {
  writeAtomically(path, [&](std::ostream& out) {
    writeHeader(out, g, e);
    const bool big = e == PlyEncoding::BinaryBigEndian;
    if (e == PlyEncoding::Ascii) {
      out << std::setprecision(9);
      for (size_t i = 0; i < g.points.size(); ++i) {
        const Eigen::Vector3d& p = g.points[i];
        out << float(p.x()) << ' ' << float(p.y()) << ' ' << float(p.z());
        if (g.colourKind == ColourKind::rgb)
          for (int k = 0; k < 3; ++k) out << ' ' << int(colourByte(g.colours[i][k]));
        if (g.colourKind == ColourKind::intensity) out << ' ' << g.colours[i][0];
        out << '\n';
      }
      for (int32_t c : g.cell) out << (c < 0 ? "0" : "1 " + std::to_string(c)) << '\n';
      return;
    }
    for (size_t i = 0; i < g.points.size(); ++i) {
      for (int k = 0; k < 3; ++k) putBinary(out, static_cast<float>(g.points[i][k]), big);
      if (g.colourKind == ColourKind::rgb)
        for (int k = 0; k < 3; ++k) putBinary(out, colourByte(g.colours[i][k]), big);
      if (g.colourKind == ColourKind::intensity) putBinary(out, g.colours[i][0], big);
    }
    for (int32_t c : g.cell) {
      putBinary<uint8_t>(out, c < 0 ? 0 : 1, big);
      if (c >= 0) putBinary<int32_t>(out, c, big);
    }
  });
}

}  // namespace rangefuse::io
