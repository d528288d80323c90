#include "VertexColours.h"

#include <map>
#include <string>

#include "rangefuse/core/Error.h"

namespace rangefuse::io::internal {
namespace {

/// The largest value of an integer PLY type; 1 for floats (taken as they are).
double fullScale(PlyType t) {
  static const std::map<PlyType, double> kLargest = {
      {PlyType::Int8, 127},     {PlyType::UInt8, 255},          {PlyType::Int16, 32767},
      {PlyType::UInt16, 65535}, {PlyType::Int32, 2147483647.0}, {PlyType::UInt32, 4294967295.0}};
  const auto it = kLargest.find(t);
  return it == kLargest.end() ? 1 : it->second;
}

PlyType typeOf(const PlyElementData& e, const std::string& name) {
  for (const PlyProperty& p : e.element.properties)
    if (p.name == name) return p.type;
  return PlyType::Float32;
}

/// Columns of the first of `names` sets that the element has in full, or an empty list.
std::vector<std::string> firstComplete(const PlyElementData& e,
                                       const std::vector<std::vector<std::string>>& names) {
  for (const auto& set : names) {
    bool all = true;
    for (const std::string& n : set) all = all && e.scalarColumn(n) >= 0;
    if (all) return set;
  }
  return {};
}

}  // namespace

std::vector<Colour> elementColours(const std::string& path, const PlyElementData& e,
                                   ColourKind& kind) {
  std::vector<std::string> names = firstComplete(
      e, {{"red", "green", "blue"}, {"diffuse_red", "diffuse_green", "diffuse_blue"}});
  kind = ColourKind::rgb;
  if (names.empty()) {
    names = firstComplete(e, {{"intensity"}});
    kind = ColourKind::intensity;
  }
  if (names.empty()) {
    kind = ColourKind::none;
    return {};
  }
  int column[3];
  double scale[3];
  for (int k = 0; k < 3; ++k) {
    const std::string& name = names[names.size() == 3 ? k : 0];
    column[k] = e.scalarColumn(name);
    scale[k] = 1 / fullScale(typeOf(e, name));
  }
  std::vector<Colour> colours(e.element.count);
  for (uint64_t i = 0; i < e.element.count; ++i)
    for (int k = 0; k < 3; ++k) {
      const double c = e.scalar(i, column[k]) * scale[k];
      if (!(c >= 0 && c <= 1))
        throw InputError(path + ": " + e.element.name + " #" + std::to_string(i) + ": " +
                         names[names.size() == 3 ? k : 0] + " " +
                         std::to_string(e.scalar(i, column[k])) +
                         " is outside [0, 1] (float colours and intensities must be)");
      colours[i][k] = static_cast<float>(c);
    }
  return colours;
}

}  // namespace rangefuse::io::internal
