// The simple method tests compare the distributed builds with (test-only): every rank holds
// every scan, plans the whole list of bricks and keeps its part.
#pragma once

#include <mpi.h>

#include <vector>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse::test {

/// Collective: the field of world-placed scans, every rank holding them all.
inline void replicatedFieldOf(const FieldSettings& f, std::vector<PrismScan> world, MPI_Comm comm,
                              FusedField& field) {
  field.scans = std::move(world);
  field.scanCount = field.scans.size();
  field.scanTriangles = 0;
  for (const auto& s : field.scans) field.scanTriangles += s.surface.triangles.size();
  field.layout =
      directoryOf(planBricks(field.scans, fitGrid(field.scans, f.voxel, f.brick, f.eps()),
                             mpi::size(comm), f.maxVoxels),
                  mpi::rank(comm));
  field.store = std::make_unique<BrickStore>(field.layout, mpi::rank(comm));
  if (methodInfo(f.method).closestSurface) {
    evaluateClosestSurfaceField(f, field, f.minViews);
    return;
  }
  PrismIntegrator integrator(*field.store);
  for (const auto& s : field.scans) integrator.addScan(s);
}

}  // namespace rangefuse::test
