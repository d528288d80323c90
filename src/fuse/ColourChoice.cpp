#include "rangefuse/fuse/ColourChoice.h"

#include "rangefuse/core/Error.h"

namespace rangefuse {

ColourKind chooseColour(const std::optional<ColourKind>& request,
                        const std::vector<ColourKind>& kinds, const io::ConfFile& conf,
                        std::string& note) {
  note.clear();
  if (kinds.empty() || request == ColourKind::none) return ColourKind::none;
  if (request) {
    for (size_t i = 0; i < kinds.size(); ++i)
      if (kinds[i] != *request)
        throw InputError(conf.scans[i].path + ": carries " +
                         (kinds[i] == ColourKind::none
                              ? "no colour"
                              : "colour of kind " + colourKindName(kinds[i])) +
                         ", but --colour " + colourKindName(*request) +
                         " asks every scan for it (--colour auto fuses colour only when all have "
                         "the same)");
    return *request;
  }
  for (size_t i = 1; i < kinds.size(); ++i)
    if (kinds[i] != kinds[0]) {
      note = "colour left out: " + conf.scans[0].path + " carries " + colourKindName(kinds[0]) +
             ", " + conf.scans[i].path + " " + colourKindName(kinds[i]);
      return ColourKind::none;
    }
  return kinds[0];
}

}  // namespace rangefuse
