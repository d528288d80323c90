// One rank's share of a triangle mesh that is stitched across ranks.
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse {

/// The faces one rank extracted and the vertices they use. Each vertex has exactly one owner
/// (the lowest rank using it); a rank's owned vertices are numbered consecutively from
/// firstVertex in the order of first use, so concatenating every rank's owned vertices and
/// faces in rank order gives the mesh one rank would have built.
struct MeshPart {
  TriangleMesh mesh;                     ///< local vertices (numbered by first use) and faces
  std::vector<int64_t> global;           ///< global number of each local vertex
  std::vector<int32_t> owner;            ///< owning rank of each local vertex
  int rank = 0;                          ///< the rank holding this part
  ColourKind colour = ColourKind::none;  ///< what mesh.colours holds (the same on every rank)
  bool marksFilled = false;  ///< mesh.filled holds one flag per vertex (the same on every rank)
  uint64_t filledFaces = 0;  ///< when marksFilled: faces of all ranks with a filled vertex
  double filledArea = 0;     ///< and their area
  uint64_t firstVertex = 0;  ///< global number of this rank's first owned vertex
  uint64_t ownedVertices = 0;
  uint64_t firstFace = 0;  ///< global number of this rank's first face
  uint64_t totalVertices = 0;
  uint64_t totalFaces = 0;

  bool owns(size_t local) const { return owner[local] == rank; }
};

}  // namespace rangefuse
