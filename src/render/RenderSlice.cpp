#include <algorithm>
#include <cmath>
#include <sstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/render/Render.h"

namespace rangefuse {

int slicePlane(const VoxelGrid& grid, int axis, double value) {
  return static_cast<int>(std::lround(grid.coord(Eigen::Vector3d::Constant(value), axis)));
}

Image renderSlice(const SparseField& field, int axis, double value) {
  const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
  const VoxelGrid& g = field.grid();
  const Eigen::AlignedBox3d box = field.bounds();
  if (box.isEmpty()) return Image(1, 1, 255);
  const VoxelIndex lo = g.nearest(box.min()), hi = g.nearest(box.max());
  const int nu = hi[u] - lo[u] + 1, nv = hi[v] - lo[v] + 1;
  const int scale = std::max(1, 512 / std::max(nu, nv));
  VoxelIndex at = VoxelIndex::Zero();
  at[axis] = slicePlane(g, axis, value);
  double dmax = 0;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      at[u] = lo[u] + i, at[v] = lo[v] + j;
      if (const VoxelSums* s = field.voxel(at))
        dmax = std::max(dmax, double(std::abs(s->wd / s->w)));
    }
  Image img(nu * scale, nv * scale, 0);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      at[u] = lo[u] + i, at[v] = lo[v] + j;
      const VoxelSums* s = field.voxel(at);
      uint8_t r = 40, gr = 60, b = 140;  // unobserved
      if (s) r = gr = b = static_cast<uint8_t>(255 * std::min(1.0, std::abs(s->wd / s->w) / dmax));
      for (int y = 0; y < scale; ++y)
        for (int x = 0; x < scale; ++x) img.set(i * scale + x, (nv - 1 - j) * scale + y, r, gr, b);
    }
  return img;
}

void parseView(const std::string& text, ViewSettings& view) {
  std::istringstream in(text);
  char comma = 0;
  std::string rest;
  if (!(in >> view.azimuthDeg >> comma >> view.elevationDeg) || comma != ',' || (in >> rest))
    throw InputError("--view must be AZIMUTH,ELEVATION in degrees, not '" + text + "'");
}

char upAxis(const std::string& setting, bool stations) {
  if (setting == "y" || setting == "z") return setting[0];
  if (setting == "auto") return stations ? 'z' : 'y';
  throw InputError("--up must be y, z or auto, not '" + setting + "'");
}

void parseSlice(const std::string& text, int& axis, double& value) {
  const std::string axes = "xyz";
  if (text.size() < 3 || text[1] != '=' || axes.find(text[0]) == std::string::npos)
    throw InputError("--slice must be AXIS=VALUE with AXIS x, y or z, not '" + text + "'");
  axis = static_cast<int>(axes.find(text[0]));
  std::istringstream in(text.substr(2));
  std::string rest;
  if (!(in >> value) || (in >> rest) || !std::isfinite(value))
    throw InputError("--slice value must be a number, not '" + text.substr(2) + "'");
}

}  // namespace rangefuse
