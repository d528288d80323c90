#include "rangefuse/robust/SpaceCarving.h"

#include <algorithm>

namespace rangefuse {

SpaceCarving::SpaceCarving(const std::vector<SightMap>& sights, double margin)
    : sights_(sights), margin_(margin) {
  int scans = 0;
  for (const SightMap& s : sights) scans += s.width() > 0;
  // Two thirds, rounded up: a frame's edge leaves space outside it unknown, so a point only a
  // few scans hid (their shadows beside the object) is not taken for inside.
  quorum_ = std::max(1, (2 * scans + 2) / 3);
}

std::vector<uint8_t> SpaceCarving::inside(const Eigen::AlignedBox3d& box,
                                          const std::vector<Eigen::Vector3d>& points) const {
  // Only the maps that may say anything about the box are asked, point by point.
  std::vector<const SightMap*> near;
  for (const SightMap& s : sights_)
    if (s.width() > 0 && s.mayCover(box)) near.push_back(&s);
  std::vector<uint8_t> in(points.size(), 0);
  for (size_t i = 0; i < points.size(); ++i) {
    int hidden = 0;
    bool through = false;
    for (const SightMap* s : near) {
      const SightMap::Sight sight = s->sightOf(points[i], margin_);
      if (sight == SightMap::Sight::Through) {
        through = true;  // one scan that looked through the point settles it
        break;
      }
      hidden += sight == SightMap::Sight::Behind;
    }
    in[i] = hidden >= quorum_ && !through;
  }
  return in;
}

}  // namespace rangefuse
