#include "rangefuse/pipeline/PlacedScans.h"

#include <algorithm>
#include <iterator>

#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/route/ScanRouting.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse::internal {

using mpi::collectivelyOrThrow;

Eigen::AlignedBox3d placedBounds(const LoadedScans& scans, const std::vector<size_t>& which,
                                 const std::vector<Pose>& poses, MPI_Comm comm) {
  Eigen::AlignedBox3d box;
  collectivelyOrThrow(comm, [&] {
    for (size_t i : which) {
      if (!scans.holds(i)) continue;
      // The points alone: placing the whole scan would copy its triangles just for a box.
      const std::shared_ptr<const PrismScan> scan = scans.held->get(i);
      for (const Eigen::Vector3d& p : scan->surface.points) box.extend(poses[i].apply(p));
    }
  });
  return mpi::unitedBox(box, comm);
}

IndexedScans routeWindow(const LoadedScans& scans, const std::vector<size_t>& order, size_t first,
                         size_t end, const std::vector<Pose>& poses, const BrickLayout& layout,
                         double reach, MPI_Comm comm) {
  std::vector<size_t> mine;  // one round: a window holds as many entries as ranks
  for (size_t k = first; k < end; ++k)
    if (scans.holds(order[k])) mine.push_back(k);
  const auto take = [&](size_t k) {
    return TakenScan{{}, placeScan(*scans.held->get(order[k]), poses[order[k]])};
  };
  RoutedParts parts;
  RoutingStats stats;
  if (!routeRounds({mine}, take, layout, reach, true, comm, parts, stats)) throw mpi::Reported();
  parts.sortByEntry();
  return parts.takeAll();
}

void addRouted(const LoadedScans& scans, const std::vector<size_t>& order,
               const std::vector<Pose>& poses, PrismIntegrator& integrator,
               const BrickLayout& layout, MPI_Comm comm) {
  routePlaced(scans, order, poses, layout, 0, comm,
              [&](size_t, const PrismScan& part) { integrator.addScan(part); });
}

BrickLayout planPlacedOn(const LoadedScans& scans, const std::vector<size_t>& which,
                         const std::vector<Pose>& poses, const VoxelGrid& grid, uint64_t maxVoxels,
                         int threads, MPI_Comm comm) {
  BrickWork work;
  collectivelyOrThrow(comm, [&] {
    for (size_t i : which)
      if (scans.holds(i))
        addPrismWork(placeScan(*scans.held->get(i), poses[i]), grid, maxVoxels, work, threads);
  });
  BrickLayout layout;
  collectivelyOrThrow(comm, [&] { layout = reduceBrickWork(work, grid, maxVoxels, comm); });
  return layout;
}

BrickLayout planPlaced(const LoadedScans& scans, const std::vector<size_t>& which,
                       const std::vector<Pose>& poses, const FieldSettings& f, MPI_Comm comm) {
  const Eigen::AlignedBox3d box = placedBounds(scans, which, poses, comm);
  VoxelGrid grid;
  collectivelyOrThrow(comm, [&] { grid = gridAround(box, f.voxel, f.brick, f.eps()); });
  return planPlacedOn(scans, which, poses, grid, f.maxVoxels, f.threads, comm);
}

}  // namespace rangefuse::internal
