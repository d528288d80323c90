// A mesh held in parts by many ranks, written as HDF5 datasets with an XDMF description, the
// form ParaView and VisIt open directly ("Xdmf3 Reader").
#pragma once

#include <mpi.h>

#include <string>

#include "rangefuse/core/MeshPart.h"

namespace rangefuse::io {

/// True when `path` names an XDMF mesh (ends in .xdmf).
bool isXdmfPath(const std::string& path);

/// The HDF5 file an XDMF mesh path keeps its data in: the same name ending in .h5.
std::string xdmfDataPath(const std::string& xdmfPath);

/// Collective: writes the mesh into xdmfDataPath(path) — /geometry (vertices x 3, float64),
/// /topology (faces x 3, int64 global vertex numbers) and, when the parts have normals,
/// /normals (vertices x 3, float32), and when the part is coloured /colours (vertices x 3,
/// uint8, for rgb; vertices x 1, float32, for intensity), and when it marks filled vertices
/// /filled (vertices x 1, uint8) — each rank writing its owned vertices and
/// its faces, in the order writeMeshPartPly writes them; then the XDMF text at `path`. Both are
/// written under temporary names and renamed into place once every rank succeeded. Returns false on
/// every rank if any failed (its message printed once); never leaves a rank waiting.
bool writeMeshPartXdmf(const std::string& path, const MeshPart& part, MPI_Comm comm);

}  // namespace rangefuse::io
