// Scans placed at poses for the fields registration and tracking grow (private to the fuse
// stage): each rank places the scans it read and routes their prisms to the brick owners.
#pragma once

#include <mpi.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/route/ScanRouting.h"
#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse::internal {

/// Collective: bounds of the points of every scan at its pose, each scan placed by its reader.
Eigen::AlignedBox3d placedBounds(const LoadedScans& scans, const std::vector<size_t>& which,
                                 const std::vector<Pose>& poses, MPI_Comm comm);

/// Collective: the list entries [first, end), each placed by its reader and routed to the
/// owners of the bricks its prisms touch (or, with reach > 0, lie within reach of), as
/// (position in the list, part) in list order. A scan read again may fail: all ranks throw.
IndexedScans routeWindow(const LoadedScans& scans, const std::vector<size_t>& order, size_t first,
                         size_t end, const std::vector<Pose>& poses, const BrickLayout& layout,
                         double reach, MPI_Comm comm);

/// Collective: calls fn(k, part) for the listed scans in list order (routeWindow), in windows
/// of as many scans as ranks, so that only a window is in flight, never every placed scan.
template <class Fn>
void routePlaced(const LoadedScans& scans, const std::vector<size_t>& order,
                 const std::vector<Pose>& poses, const BrickLayout& layout, double reach,
                 MPI_Comm comm, Fn&& fn) {
  const size_t window = static_cast<size_t>(mpi::size(comm));
  for (size_t first = 0; first < order.size(); first += window) {
    const size_t end = std::min(order.size(), first + window);
    for (auto& [k, part] : routeWindow(scans, order, first, end, poses, layout, reach, comm))
      fn(k, part);
  }
}

/// Collective: adds the listed scans to the field in list order.
void addRouted(const LoadedScans& scans, const std::vector<size_t>& order,
               const std::vector<Pose>& poses, PrismIntegrator& integrator,
               const BrickLayout& layout, MPI_Comm comm);

/// Collective: the bricks the prisms of the listed scans touch at their poses, planned from the
/// work of each reader's scans. The local pass (a scan read again may fail) is agreed on before
/// the collective reduction.
BrickLayout planPlacedOn(const LoadedScans& scans, const std::vector<size_t>& which,
                         const std::vector<Pose>& poses, const VoxelGrid& grid, uint64_t maxVoxels,
                         int threads, MPI_Comm comm);

/// Collective: planPlacedOn the lattice a build of the listed scans in one place would use.
BrickLayout planPlaced(const LoadedScans& scans, const std::vector<size_t>& which,
                       const std::vector<Pose>& poses, const FieldSettings& field, MPI_Comm comm);

}  // namespace rangefuse::internal
