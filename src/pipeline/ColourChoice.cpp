#include "ColourChoice.h"

#include "rangefuse/core/Error.h"

namespace rangefuse {

ColourKind chooseColour(const std::optional<ColourKind>& request,
                        const std::vector<std::optional<ColourKind>>& kinds,
                        const io::ConfFile& conf, std::string& note) {
  note.clear();
  if (request == ColourKind::none) return ColourKind::none;
  std::optional<size_t> first;  // the first scan with points
  for (size_t i = 0; i < kinds.size(); ++i) {
    if (!kinds[i]) continue;
    const ColourKind kind = *kinds[i];
    if (request && kind != *request)
      throw InputError(
          conf.scans[i].path + ": carries " +
          (kind == ColourKind::none ? "no colour" : "colour of kind " + colourKindName(kind)) +
          ", but --colour " + colourKindName(*request) +
          " asks every scan for it (--colour auto fuses colour only when all have "
          "the same)");
    if (!first) {
      first = i;
    } else if (kind != *kinds[*first]) {
      note = "colour left out: " + conf.scans[*first].path + " carries " +
             colourKindName(*kinds[*first]) + ", " + conf.scans[i].path + " " +
             colourKindName(kind);
      return ColourKind::none;
    }
  }
  return first ? *kinds[*first] : ColourKind::none;
}

}  // namespace rangefuse
