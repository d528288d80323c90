#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

BrickStore::BrickStore(const BrickLayout& layout, int rank)
    : layout_(layout), first_(layout.rankStart[rank]) {
  const int B = layout.grid.brick;
  perBrick_ = static_cast<size_t>(B) * B * B;
  for (size_t i = layout.rankStart[rank]; i < layout.rankStart[rank + 1]; ++i) {
    index_[layout.codes[i]] = static_cast<int64_t>(codes_.size());
    codes_.push_back(layout.codes[i]);
  }
  sums_.resize(codes_.size() * perBrick_);
}

size_t BrickStore::offset(size_t b, const VoxelIndex& v) const {
  return offset(b, mortonDecode(codes_[b]), v);
}

}  // namespace rangefuse
