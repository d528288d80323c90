// A mesh held in parts by many ranks, written as one binary PLY with MPI-IO.
#pragma once

#include <mpi.h>

#include <string>

#include "rangefuse/core/MeshPart.h"

namespace rangefuse::io {

/// Collective: every rank writes its owned vertices and its faces at computed offsets of one
/// file: the same bytes writeMeshPly writes for the gathered mesh (normals when part.mesh has
/// them). Written to `path`.tmp and renamed into place only when every rank's write and sync
/// succeeded. Returns false on every rank if any failed (its message printed once, the
/// temporary removed); never leaves a rank waiting for another.
bool writeMeshPartPly(const std::string& path, const MeshPart& part, MPI_Comm comm);

}  // namespace rangefuse::io
