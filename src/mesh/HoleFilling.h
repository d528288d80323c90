// Carving for closed meshes (private to the mesh stage): the values of voxels no scan
// observed, and the bricks no scan reached that a closed surface passes through.
#pragma once

#include <mpi.h>

#include <map>
#include <vector>

#include "rangefuse/mesh/DistributedMesh.h"

namespace rangefuse::internal {

/// Collective: the brick coordinates [lo, hi] of every rank's bricks, one brick wider each
/// way (so that a fill closes inside it); lo > hi when the field has none.
void fillRegion(const BrickLayout& layout, MPI_Comm comm, BrickCoord& lo, BrickCoord& hi);

/// Gives the NaN (unobserved) voxels of brick `code`'s values their carved value; returns one
/// flag per voxel, 1 where carved.
std::vector<uint8_t> carveBrick(uint64_t code, const VoxelGrid& grid, const HoleFill& fill,
                                std::vector<float>& values);

/// The bricks in [lo, hi] whose codes lie in rank `me`'s range, that `layout` does not hold, and
/// whose cubes (their voxels and the first layer of their upper neighbours) reach inside space:
/// every voxel carved (so their voxels need no flags: a brick without flags reads as carved).
std::map<uint64_t, std::vector<float>> fillBricks(const BrickLayout& layout, const BrickCoord& lo,
                                                  const BrickCoord& hi, const HoleFill& fill,
                                                  int me, int threads);

/// `layout` with this rank's fill bricks beside its own, its border no longer known (a fill
/// brick of another rank may border this rank's), for halos and stitching.
BrickLayout withFillBricks(const BrickLayout& layout,
                           const std::map<uint64_t, std::vector<float>>& fill);

}  // namespace rangefuse::internal
