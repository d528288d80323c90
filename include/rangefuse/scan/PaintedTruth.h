// The coloured ground-truth mesh of a textured synthetic scene.
#pragma once

#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse {

/// `mesh` coloured with checkColour(vertex, size) at its vertices. A vertex colour is
/// interpolated across each triangle, which would blur a check edge over a whole triangle, so
/// triangles are split 1 to 4 at their edge midpoints until their edges are no longer than a
/// quarter check (no check hides inside a triangle whose corners share a colour), and those
/// whose corners differ in colour until their edges are shorter than `finest`: the truth's
/// edges are then about `finest` wide. The surface does not move (midpoints lie on it), so
/// distances to the mesh are unchanged.
TriangleMesh paintedTruth(const TriangleMesh& mesh, double size, double finest);

}  // namespace rangefuse
