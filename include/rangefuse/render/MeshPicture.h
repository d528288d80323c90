// Pictures of the fused mesh: what `fuse --preview` writes. Drawing the mesh's triangles costs
// a small part of the fusion, where ray casting the field would cost more than the fusion.
#pragma once

#include <mpi.h>

#include "rangefuse/core/Image.h"
#include "rangefuse/core/MeshPart.h"
#include "rangefuse/render/Render.h"

namespace rangefuse {

/// Collective: the mesh whose parts the ranks hold, drawn on `root` (blank elsewhere). The orbit
/// view frames the whole mesh; a camera view (view.camera) looks from there with view.focal,
/// dropping triangles closer than a hundredth of view.farthest. Faces seen from the front are
/// shaded in the mesh's colours (a warm grey without), from behind in a cool grey, so that a
/// hole shows what is behind it. Every rank draws its own faces into a depth buffer, and the
/// nearest face wins each pixel (on a tie, the darker packed colour): the same picture on any
/// number of ranks.
Image pictureOfMesh(const MeshPart& part, const ViewSettings& view, int root, MPI_Comm comm);

}  // namespace rangefuse
