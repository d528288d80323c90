// Rasterisation of fundamental prisms: the voxels a prism holds, found row by row.
#pragma once

#include <cstdint>
#include <functional>

#include "rangefuse/prism/Prism.h"
#include "rangefuse/volume/VoxelGrid.h"

namespace rangefuse {

using PrismVisitor = std::function<void(const VoxelIndex&, const PrismHit&)>;

/// Visits every voxel centre inside the prism: visit(VoxelIndex, PrismHit), each once. Rows
/// of the bounding box are cut to the prism's slabs, so most outside voxels are never solved
/// for. (The field's integrator uses the same rows with its own batches.)
void rasterizePrism(const Prism& prism, const VoxelGrid& grid, const PrismVisitor& visit);

/// Reference for rasterizePrism: solves at every voxel of the bounding box.
void rasterizePrismBruteForce(const Prism& prism, const VoxelGrid& grid, const PrismVisitor& visit);

}  // namespace rangefuse
