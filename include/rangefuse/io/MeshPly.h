// Triangle mesh and point PLY reading and writing.
#pragma once

#include <string>

#include "rangefuse/core/Colour.h"
#include "rangefuse/core/Limits.h"
#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse::io {

/// Reads vertices (x, y, z), their colours when present (`red green blue` or `intensity`, in
/// [0, 1]) and, when present, faces (polygons are fanned into triangles).
TriangleMesh readMeshPly(const std::string& path, const InputLimits& limits = {});

/// The same from bytes in memory; `name` heads every message.
TriangleMesh parseMeshPly(const std::string& name, const std::string& text,
                          const InputLimits& limits = {});

/// Writes binary little-endian PLY with float vertices (double when far from the origin, where
/// a float's step exceeds 1/1000 of the mean edge), optional float normals, the vertex colours
/// if the mesh has them (uchar red green blue, or a float intensity) and int faces; written to
/// a temporary name and renamed into place when complete.
void writeMeshPly(const std::string& path, const TriangleMesh& mesh,
                  ColourKind colour = ColourKind::rgb);

}  // namespace rangefuse::io
