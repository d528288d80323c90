// Colour and intensity properties of a PLY element, as the readers of meshes and range grids
// find them.
#pragma once

#include <vector>

#include "PlyFile.h"
#include "rangefuse/core/Colour.h"

namespace rangefuse::io::internal {

/// The element's colours: `red green blue` (or `diffuse_red ...`), else `intensity`, else
/// none (`kind` says which). Integer channels are scaled by their type's largest value, float
/// channels taken as they are; every channel must then lie in [0, 1] (InputError naming the
/// file and the item otherwise).
std::vector<Colour> elementColours(const std::string& path, const PlyElementData& e,
                                   ColourKind& kind);

}  // namespace rangefuse::io::internal
