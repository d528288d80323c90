// Global vertex numbering, normals and gathering of mesh parts held by different ranks.
#pragma once

#include <mpi.h>

#include "rangefuse/core/MeshPart.h"
#include "rangefuse/mesh/MarchingCubes.h"
#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse {

/// Collective: turns this rank's marching-cubes piece (cubes of its own bricks of `layout`)
/// into a MeshPart. Ranks whose cubes share a lattice edge agree that the lowest of them owns
/// its vertex; owned counts are scanned into global numbers. Only boundary keys travel.
MeshPart stitchPiece(const MeshPiece& piece, const BrickLayout& layout, MPI_Comm comm);

/// Collective: area-weighted normals of the owned vertices (others are left zero), summed in
/// global face order so that they are the bits vertexNormals gives on the whole mesh.
void addPartNormals(MeshPart& part, MPI_Comm comm);

/// Collective: the whole mesh on `root` (empty elsewhere). For tests and small meshes only:
/// the point of a MeshPart is that no rank needs the whole mesh.
TriangleMesh gatherMesh(const MeshPart& part, int root, MPI_Comm comm);

}  // namespace rangefuse
