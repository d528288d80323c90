#include "rangefuse/io/MeshPly.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "PlyFile.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {
namespace {

void readFaces(const internal::PlyFile& f, TriangleMesh& m) {
  const internal::PlyElementData* e = f.find("face");
  if (!e) return;
  int li = e->listIndex("vertex_indices");
  if (li < 0) li = e->listIndex("vertex_index");
  if (li < 0) throw InputError(f.path + ": face lacks list 'vertex_indices'");
  const auto& off = e->listOffsets[li];
  const auto& val = e->listValues[li];
  const int64_t nv = static_cast<int64_t>(m.vertices.size());
  for (uint64_t i = 0; i < e->element.count; ++i) {
    for (uint32_t k = off[i]; k < off[i + 1]; ++k)
      if (val[k] < 0 || val[k] >= nv)
        throw InputError(f.path + ": face #" + std::to_string(i) + ": vertex index " +
                         std::to_string(val[k]) + " out of range (" + std::to_string(nv) +
                         " vertices)");
    if (off[i + 1] - off[i] < 3)
      throw InputError(f.path + ": face #" + std::to_string(i) + " has fewer than 3 vertices");
    for (uint32_t k = off[i] + 2; k < off[i + 1]; ++k)
      m.faces.push_back({static_cast<int32_t>(val[off[i]]), static_cast<int32_t>(val[k - 1]),
                         static_cast<int32_t>(val[k])});
  }
}

template <class T>
void put(std::ostream& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.write(b, sizeof(T));  // the project targets little-endian hosts (x86-64, aarch64)
}

/// Float vertices keep files small, but far from the origin (a survey's coordinates with
/// millimetre voxels) a float's step would be a sizeable part of an edge: then doubles.
bool needsDoubleVertices(const TriangleMesh& m) {
  double maxAbs = 0, edges = 0;
  for (const auto& v : m.vertices) maxAbs = std::max(maxAbs, v.cwiseAbs().maxCoeff());
  for (const auto& t : m.faces) edges += (m.vertices[t[0]] - m.vertices[t[1]]).norm();
  const double floatStep = maxAbs * std::ldexp(1.0, -23);
  if (m.faces.empty()) return floatStep > 1e-6;
  return floatStep > 1e-3 * edges / static_cast<double>(m.faces.size());
}

TriangleMesh meshFrom(const internal::PlyFile& f) {
  const std::string& path = f.path;
  const internal::PlyElementData* v = f.find("vertex");
  if (!v) throw InputError(path + ": no 'vertex' element");
  int cx = v->scalarColumn("x"), cy = v->scalarColumn("y"), cz = v->scalarColumn("z");
  if (cx < 0 || cy < 0 || cz < 0) throw InputError(path + ": vertex lacks x, y or z");
  TriangleMesh m;
  m.vertices.resize(v->element.count);
  for (uint64_t i = 0; i < v->element.count; ++i) {
    Eigen::Vector3d p(v->scalar(i, cx), v->scalar(i, cy), v->scalar(i, cz));
    if (!p.allFinite())
      throw InputError(path + ": vertex #" + std::to_string(i) + " has a NaN or Inf coordinate");
    m.vertices[i] = p;
  }
  readFaces(f, m);
  return m;
}

}  // namespace

TriangleMesh parseMeshPly(const std::string& name, const std::string& text,
                          const InputLimits& limits) {
  return meshFrom(internal::parsePly(name, text, limits.maxElements));
}

TriangleMesh readMeshPly(const std::string& path, const InputLimits& limits) {
  return meshFrom(internal::readPly(path, limits.maxElements));
}

void writeMeshPly(const std::string& path, const TriangleMesh& mesh) {
  const bool normals = !mesh.normals.empty();
  const bool wide = needsDoubleVertices(mesh);
  writeAtomically(path, [&](std::ostream& out) {
    const char* type = wide ? "double" : "float";
    out << "ply\nformat binary_little_endian 1.0\ncomment written by rangefuse\n"
        << "element vertex " << mesh.vertices.size() << "\n"
        << "property " << type << " x\nproperty " << type << " y\nproperty " << type << " z\n";
    if (normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
    out << "element face " << mesh.faces.size() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        if (wide)
          put(out, mesh.vertices[i][k]);
        else
          put(out, static_cast<float>(mesh.vertices[i][k]));
      }
      if (normals)
        for (int k = 0; k < 3; ++k) put(out, static_cast<float>(mesh.normals[i][k]));
    }
    for (const auto& t : mesh.faces) {
      put<uint8_t>(out, 3);
      for (int k = 0; k < 3; ++k) put<int32_t>(out, t[k]);
    }
  });
}

}  // namespace rangefuse::io
