// Which colour a fused field carries: what the user asked for against what the scans hold.
#pragma once

#include <optional>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/io/Conf.h"

namespace rangefuse {

/// The colour the field takes, given `kinds` (what each of conf's scans carries, in order; none
/// for a scan with no points, which does not count).
/// No `request` (--colour auto): the scans' kind when every scan has the same one, else none
/// (`note` says why, when some scans have colour). A request of rgb or intensity needs every
/// scan to carry it: InputError naming the first that does not. A request of none: none.
ColourKind chooseColour(const std::optional<ColourKind>& request,
                        const std::vector<std::optional<ColourKind>>& kinds,
                        const io::ConfFile& conf, std::string& note);

}  // namespace rangefuse
