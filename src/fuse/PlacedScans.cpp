#include "PlacedScans.h"

#include <algorithm>
#include <iterator>

#include "rangefuse/fuse/ScanLoader.h"
#include "rangefuse/parallel/Mpi.h"
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
  MPI_Allreduce(MPI_IN_PLACE, box.min().data(), 3, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, box.max().data(), 3, MPI_DOUBLE, MPI_MAX, comm);
  return box;
}

IndexedScans routeWindow(const LoadedScans& scans, const std::vector<size_t>& order, size_t first,
                         size_t end, const std::vector<Pose>& poses, const BrickLayout& layout,
                         double reach, MPI_Comm comm) {
  const int me = mpi::rank(comm);
  std::vector<std::vector<char>> out(mpi::size(comm));
  IndexedScans parts;
  RoutingStats stats;
  stats.bytes.assign(out.size(), 0);
  collectivelyOrThrow(comm, [&] {
    for (size_t k = first; k < end; ++k)
      if (scans.holds(order[k]))
        routeScan(k, placeScan(*scans.held->get(order[k]), poses[order[k]]), layout, reach, me, out,
                  parts, stats);
  });
  IndexedScans received = unpackRouted(mpi::exchangeBytes(std::move(out), comm));
  std::move(received.begin(), received.end(), std::back_inserter(parts));
  std::sort(parts.begin(), parts.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  return parts;
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
                       const std::vector<Pose>& poses, const FuseOptions& o, MPI_Comm comm) {
  const Eigen::AlignedBox3d box = placedBounds(scans, which, poses, comm);
  VoxelGrid grid;
  collectivelyOrThrow(comm,
                      [&] { grid = gridAround(box, o.voxel, o.brick, o.envelope * o.voxel); });
  return planPlacedOn(scans, which, poses, grid, o.limits.maxVoxels, o.threads, comm);
}

}  // namespace rangefuse::internal
