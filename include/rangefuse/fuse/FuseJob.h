// The main job: scans + poses -> prism fields on distributed bricks -> stitched mesh.
#pragma once

#include <mpi.h>

#include <string>

#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

struct FuseOptions {
  std::string scans;       ///< .conf file
  std::string out;         ///< mesh .ply
  double voxel = 0;        ///< in the scans' units
  double envelope = 3.0;   ///< prism half-thickness, in voxels
  int brick = 8;           ///< voxels per brick edge
  float minWeight = 0.0f;  ///< voxels with summed weight not above this are unobserved
  bool normals = true;     ///< write vertex normals
  SurfaceOptions surface;
};

/// Runs the job on every rank of comm. Returns the process exit code: 0 on success, 1 when
/// any rank failed (the failure is printed once, by the lowest failing rank).
int runFuse(const FuseOptions& options, MPI_Comm comm);

}  // namespace rangefuse
