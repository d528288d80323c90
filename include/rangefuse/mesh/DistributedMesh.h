// Marching cubes over the distributed bricks, stitched across ranks without gathering.
#pragma once

#include <mpi.h>

#include <Eigen/Geometry>
#include <functional>

#include "rangefuse/core/MeshPart.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

struct MeshStats {
  uint64_t haloBricksReceived = 0;
  uint64_t localTriangles = 0;
};

/// Closing holes (--fill-holes): every voxel no scan observed gets a value, so that marching
/// cubes closes the surface across what the scanners missed.
struct HoleFill {
  /// For voxel centres within a box (world): 1 for each that lies inside (hidden behind what
  /// the scans saw, seen through by none), 0 for empty or unknown space. The same answer on
  /// every rank, whatever else it is asked.
  std::function<std::vector<uint8_t>(const Eigen::AlignedBox3d&,
                                     const std::vector<Eigen::Vector3d>&)>
      inside;
  float value = 1;  ///< the distance an unobserved voxel gets: -value inside, +value outside
};

/// Fused distance d = sum(w d) / sum(w) of every voxel of local brick b; NaN where the
/// weight is not above minWeight (unobserved).
std::vector<float> brickDistances(const BrickStore& store, size_t b, float minWeight);

/// Each rank extracts the cubes whose min corner lies in its bricks, reading the +1 layer
/// from neighbour bricks (exchanged between ranks), and returns its part of the stitched
/// mesh: vertices named by global lattice edge, so there are no duplicates or cracks, each
/// owned by one rank and numbered as one rank would number the whole mesh. `threads` share a
/// rank's bricks; any count gives the same mesh. With `fill`, unobserved voxels in the box of
/// the field's bricks (a brick wider each way) are carved: bricks no scan reached join the
/// rank whose range of codes holds them where their cubes meet inside space, and every vertex
/// on an edge with a carved end is marked filled (mesh.filled).
MeshPart extractDistributedMesh(const BrickStore& store, float minWeight, MPI_Comm comm,
                                MeshStats* stats = nullptr, int threads = 1,
                                const HoleFill* fill = nullptr);

}  // namespace rangefuse
