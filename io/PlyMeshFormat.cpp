#include "rangefuse/io/PlyMeshFormat.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rangefuse::io::internal {
namespace {

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));  // the project targets little-endian hosts (x86-64, aarch64)
}

}  // namespace

std::string PlyMeshFormat::header() const {
  const char* type = wide ? "double" : "float";
  std::string h = "ply\nformat binary_little_endian 1.0\ncomment written by rangefuse\n";
  h += "element vertex " + std::to_string(vertices) + "\n";
  for (const char* axis : {"x", "y", "z"}) h += std::string("property ") + type + " " + axis + "\n";
  if (normals) h += "property float nx\nproperty float ny\nproperty float nz\n";
  if (colour == ColourKind::rgb)
    h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (colour == ColourKind::intensity) h += "property float intensity\n";
  if (filled) h += "property uchar filled\n";
  h += "element face " + std::to_string(faces) + "\n";
  h += "property list uchar int vertex_indices\nend_header\n";
  return h;
}

double floatStep(double maxAbs) {
  return maxAbs * std::ldexp(1.0, -23);
}

int64_t edgeUnits(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step) {
  return step > 0 ? std::llround(16 * (a - b).norm() / step) : 0;
}

bool needsDoubleVertices(double maxAbs, int64_t edgeUnitsSum, uint64_t faces) {
  if (faces == 0) return floatStep(maxAbs) > 1e-6;
  if (maxAbs == 0) return false;
  // step > 1e-3 * mean edge, with the edges in units of step / 16.
  return static_cast<double>(edgeUnitsSum) < 16e3 * static_cast<double>(faces);
}

void encodeVertex(std::string& out, const PlyMeshFormat& f, const Eigen::Vector3d& p,
                  const Eigen::Vector3d* normal, const Colour* colour, uint8_t filled) {
  for (int k = 0; k < 3; ++k) {
    if (f.wide)
      put(out, p[k]);
    else
      put(out, static_cast<float>(p[k]));
  }
  if (f.normals)
    for (int k = 0; k < 3; ++k) put(out, static_cast<float>((*normal)[k]));
  if (f.colour == ColourKind::rgb)
    for (int k = 0; k < 3; ++k) put(out, colourByte((*colour)[k]));
  if (f.colour == ColourKind::intensity) put(out, (*colour)[0]);
  if (f.filled) put(out, filled);
}

void encodeFace(std::string& out, int32_t a, int32_t b, int32_t c) {
  put<uint8_t>(out, 3);
  put(out, a);
  put(out, b);
  put(out, c);
}

}  // namespace rangefuse::io::internal
