// Internal: where `fuse --preview` looks from.
#pragma once

#include <mpi.h>

#include <string>

#include "rangefuse/core/MeshPart.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/render/Render.h"

namespace rangefuse::internal {

/// Collective: the view of the preview. `view` ("AZIMUTH,ELEVATION") chooses an orbit view.
/// Without it, a scene whose first scan is a station or a depth frame is seen from that sensor,
/// looking at the middle of the mesh (a station) or as the camera looked (a depth frame), out to
/// the far side of the mesh; scans of an object are seen from the default orbit view. `up`
/// (y, z or auto: z for stations) is the orbit's up axis.
ViewSettings previewView(const std::string& view, const std::string& up, const LoadedScans& scans,
                         const MeshPart& mesh, MPI_Comm comm);

}  // namespace rangefuse::internal
