// Algorithm 2's fits as one joint solve per iteration (JointSolve.h), fed from the field's
// voxels on every rank.
#pragma once

#include <mpi.h>

#include <vector>

#include "rangefuse/register/ControlRouting.h"
#include "rangefuse/register/Correspondences.h"
#include "rangefuse/register/JointSolve.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// What one joint step needs.
struct JointStepSettings {
  size_t anchor = 0;               ///< fixes the gauge: never moves
  size_t minCorrespondences = 50;  ///< a scan with fewer points in shared voxels stays
  double maxStep = 1e300;        ///< largest motion of a step (world units, at the frame's length)
  CorrespondenceSettings field;  ///< which voxels count
};

/// Collective: one Gauss-Newton step of every pose against `store` (built at any poses: it
/// gives each voxel's plane normal and which voxels count, the scans give the planes). Returns
/// every scan's step, identical on every rank for any rank count.
std::vector<RegistrationStep> jointStep(std::vector<Pose>& poses, const BrickStore& store,
                                        ControlRouting& control, const JointStepSettings& settings,
                                        MPI_Comm comm);

}  // namespace rangefuse
