#include "rangefuse/io/MeshPly.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "PlyFile.h"
#include "VertexColours.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/PlyMeshFormat.h"

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
  ColourKind kind;
  m.colours = internal::elementColours(path, *v, kind);
  if (const int cf = v->scalarColumn("filled"); cf >= 0)
    for (uint64_t i = 0; i < v->element.count; ++i) m.filled.push_back(v->scalar(i, cf) != 0);
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

void writeMeshPly(const std::string& path, const TriangleMesh& mesh, ColourKind colour) {
  double maxAbs = 0;
  for (const auto& v : mesh.vertices) maxAbs = std::max(maxAbs, v.cwiseAbs().maxCoeff());
  int64_t edges = 0;
  const double step = internal::floatStep(maxAbs);
  for (const auto& t : mesh.faces)
    edges += internal::edgeUnits(mesh.vertices[t[0]], mesh.vertices[t[1]], step);
  internal::PlyMeshFormat f;
  f.vertices = mesh.vertices.size();
  f.faces = mesh.faces.size();
  f.wide = internal::needsDoubleVertices(maxAbs, edges, f.faces);
  f.normals = !mesh.normals.empty();
  f.colour = mesh.colours.empty() ? ColourKind::none : colour;
  f.filled = !mesh.filled.empty();
  writeAtomically(path, [&](std::ostream& out) {
    std::string buf = f.header();
    const auto flushFull = [&] {
      if (buf.size() < (1 << 20)) return;
      out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    };
    for (size_t i = 0; i < mesh.vertices.size(); ++i, flushFull())
      internal::encodeVertex(buf, f, mesh.vertices[i], f.normals ? &mesh.normals[i] : nullptr,
                             f.colour != ColourKind::none ? &mesh.colours[i] : nullptr,
                             f.filled ? mesh.filled[i] : 0);
    for (const auto& t : mesh.faces) {
      internal::encodeFace(buf, t[0], t[1], t[2]);
      flushFull();
    }
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  });
}

}  // namespace rangefuse::io
