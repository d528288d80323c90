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

/// "sphere", "torus" or "composite", each about 100 units across, or "room" (8 m across);
/// throws InputError.
TriangleMesh makeShape(const std::string& name);

/// Appends b's vertices and faces to a.
void appendMesh(TriangleMesh& a, const TriangleMesh& b);

}  // namespace rangefuse
