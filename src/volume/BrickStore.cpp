#include "rangefuse/volume/BrickStore.h"

#include <algorithm>

namespace rangefuse {
namespace {

/// Moves brick slot[k] of `data` (bricks of `per` values) to position k, following each cycle
/// of the permutation through one scratch brick.
template <class T>
void permuteBricks(std::vector<T>& data, const std::vector<size_t>& slot, size_t per) {
  std::vector<T> scratch(per);
  std::vector<char> done(slot.size(), 0);
  auto brick = [&](size_t b) { return data.begin() + static_cast<std::ptrdiff_t>(b * per); };
  for (size_t start = 0; start < slot.size(); ++start) {
    if (done[start] || slot[start] == start) continue;
    std::copy(brick(start), brick(start + 1), scratch.begin());
    size_t k = start;
    while (slot[k] != start) {
      std::copy(brick(slot[k]), brick(slot[k] + 1), brick(k));
      done[k] = 1;
      k = slot[k];
    }
    std::copy(scratch.begin(), scratch.end(), brick(k));
    done[k] = 1;
  }
}

}  // namespace

BrickStore::BrickStore(const BrickLayout& layout, int rank) : layout_(layout), rank_(rank) {
  const int B = layout.grid.brick;
  perBrick_ = static_cast<size_t>(B) * B * B;
  codes_.assign(layout.codes.begin() + static_cast<std::ptrdiff_t>(layout.rankStart[rank]),
                layout.codes.begin() + static_cast<std::ptrdiff_t>(layout.rankStart[rank + 1]));
  index_.assign(codes_);
  sums_.resize(codes_.size() * perBrick_);
}

void BrickStore::grow(const BrickLayout& layout, const std::vector<uint64_t>& fresh) {
  layout_ = layout;
  for (const uint64_t code : fresh) {
    if (code < (codes_.empty() ? 0 : codes_.back())) ordered_ = false;
    index_.set(code, static_cast<int64_t>(codes_.size()));
    codes_.push_back(code);
  }
  // A quarter of room, not the vector's doubling: a growing field on many ranks holds at most
  // a quarter more than its bricks, and a copy moves each brick about five times in all.
  const size_t voxels = codes_.size() * perBrick_;
  if (voxels > sums_.capacity()) sums_.reserve(voxels + voxels / 4);
  sums_.resize(voxels);
  if (hasColour() && voxels > colours_.capacity()) colours_.reserve(voxels + voxels / 4);
  if (hasColour()) colours_.resize(voxels);
}

void BrickStore::rehome(const BrickLayout& layout, const std::vector<uint64_t>& arriving) {
  const auto moveBrick = [&](auto& voxels, size_t from, size_t to) {
    std::copy_n(voxels.begin() + from * perBrick_, perBrick_, voxels.begin() + to * perBrick_);
  };
  for (size_t b = 0; b < codes_.size();) {
    if (layout.ownerOfCode(codes_[b]) == rank_) {
      ++b;
      continue;
    }
    const size_t last = codes_.size() - 1;
    if (b != last) {
      moveBrick(sums_, last, b);
      if (hasColour()) moveBrick(colours_, last, b);
      codes_[b] = codes_[last];
      ordered_ = false;
    }
    codes_.pop_back();
  }
  index_.assign(codes_);  // the bricks that stay, some in new places
  sums_.resize(codes_.size() * perBrick_);
  if (hasColour()) colours_.resize(sums_.size());
  grow(layout, arriving);  // the arriving bricks' voxels are made anew: zero
}

void BrickStore::enableColour(ColourKind kind) {
  colourKind_ = kind;
  colours_.resize(sums_.size());
}

uint64_t BrickStore::bytes() const {
  return sizeof(VoxelSums) * sums_.capacity() + sizeof(VoxelColour) * colours_.capacity() +
         sizeof(uint64_t) * codes_.capacity() + index_.bytes();
}

void BrickStore::sortBricks() {
  if (ordered_) return;
  // slot[k]: where the brick that belongs at sorted position k is now. Follow each cycle of
  // that permutation, moving one brick at a time through a scratch brick.
  std::vector<size_t> slot(codes_.size());
  for (size_t k = 0; k < slot.size(); ++k) slot[k] = k;
  std::sort(slot.begin(), slot.end(), [&](size_t a, size_t b) { return codes_[a] < codes_[b]; });
  permuteBricks(sums_, slot, perBrick_);
  if (hasColour()) permuteBricks(colours_, slot, perBrick_);
  std::sort(codes_.begin(), codes_.end());
  index_.assign(codes_);
  ordered_ = true;
}

size_t BrickStore::offset(size_t b, const VoxelIndex& v) const {
  return offset(b, mortonDecode(codes_[b]), v);
}

}  // namespace rangefuse
