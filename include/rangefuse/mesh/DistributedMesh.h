// Marching cubes over the distributed bricks, stitched across ranks without gathering.
#pragma once

#include <mpi.h>

#include "rangefuse/core/MeshPart.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

struct MeshStats {
  uint64_t haloBricksReceived = 0;
  uint64_t localTriangles = 0;
};

/// Fused distance d = sum(w d) / sum(w) of every voxel of local brick b; NaN where the
/// weight is not above minWeight (unobserved).
std::vector<float> brickDistances(const BrickStore& store, size_t b, float minWeight);

/// Each rank extracts the cubes whose min corner lies in its bricks, reading the +1 layer
/// from neighbour bricks (exchanged between ranks), and returns its part of the stitched
/// mesh: vertices named by global lattice edge, so there are no duplicates or cracks, each
/// owned by one rank and numbered as one rank would number the whole mesh. `threads` share a
/// rank's bricks; any count gives the same mesh.
MeshPart extractDistributedMesh(const BrickStore& store, float minWeight, MPI_Comm comm,
                                MeshStats* stats = nullptr, int threads = 1);

}  // namespace rangefuse
