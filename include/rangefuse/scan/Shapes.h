// Built-in closed test shapes for the synthetic scanner.
#pragma once

#include <string>

#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse {

/// UV sphere with outward-facing triangles.
TriangleMesh makeSphere(const Eigen::Vector3d& centre, double radius, int rings, int segments);

/// Torus around the z axis: ring radius R, tube radius r.
TriangleMesh makeTorus(const Eigen::Vector3d& centre, double R, double r, int ringSegments,
                       int tubeSegments);

/// A non-convex composite with a through-hole: a torus with two spheres beside it, apart
/// from each other (no overlapping surfaces, so every face is a true surface).
TriangleMesh makeComposite();

/// An axis-aligned box with outward triangles, each face in square cells of at most `cell`;
/// without its bottom face when `bottom` is false (furniture standing on a floor).
TriangleMesh makeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, bool bottom,
                     double cell);

/// A room 8 x 6 x 3 (metres) seen from inside, with a desk, a cabinet, a low cube and a ball:
/// a scene for terrestrial scanner stations.
TriangleMesh makeRoom();

/// A desk 1.2 x 0.8 m on four legs with a monitor, a keyboard, a book, a ball and a ring lying
/// on it: a scene for hand-held depth cameras, with no axis of symmetry, as real desks have.
TriangleMesh makeDesk();

/// "sphere", "torus" or "composite", each about 100 units across, "room" (8 m across) or
/// "desk" (1.2 m);
/// throws InputError.
TriangleMesh makeShape(const std::string& name);

/// Appends b's vertices and faces to a.
void appendMesh(TriangleMesh& a, const TriangleMesh& b);

}  // namespace rangefuse
