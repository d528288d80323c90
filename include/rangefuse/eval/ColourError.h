// How well a coloured mesh keeps the colour of a coloured reference: the error at its vertices
// and how much of the step across texture edges survives.
#pragma once

#include <cstddef>

#include "rangefuse/core/TriangleMesh.h"
#include "rangefuse/eval/MeshDistance.h"

namespace rangefuse {

struct ColourComparison {
  size_t vertices = 0;  ///< mesh vertices compared (those within the distance limit)
  /// Per compared vertex, the mean over channels of |mesh colour - reference colour|, in
  /// 0..255 steps.
  DistanceStats error;
  /// The mesh's colour step along its edges that cross a texture edge of the reference,
  /// projected on the reference's step and divided by it (a least-squares slope over those
  /// edges): 1 when the edge is as sharp as in the reference, less when fusion blurs it.
  double edgeContrast = 0;
  size_t edges = 0;  ///< mesh edges that cross a texture edge of the reference
  /// The error split by distance from the reference's nearest texture edge: vertices within
  /// the `nearEdge` distance, and the others. Where fusion blurs colour, the first shows it.
  DistanceStats nearEdgeError, farEdgeError;
  size_t nearEdgeVertices = 0, farEdgeVertices = 0;
};

/// The step between two vertices' reference colours (Euclidean, channels in [0, 1]) from which
/// a mesh edge counts as crossing a texture edge.
constexpr double kTextureEdgeStep = 0.1;

/// Compares the vertex colours of `mesh` with those of `reference` at the reference's closest
/// point (its corner colours interpolated there). Vertices farther than `maxDistance` from the
/// reference are not compared: their colour belongs to no reference surface. A texture edge
/// runs through the middle of each reference edge whose ends differ by kTextureEdgeStep; a
/// vertex within `nearEdge` of one counts as near an edge. Both meshes must have colours.
ColourComparison compareColours(const TriangleMesh& mesh, const TriangleMesh& reference,
                                double maxDistance, double nearEdge);

}  // namespace rangefuse
