#include "rangefuse/volume/CodeIndex.h"

namespace rangefuse::internal {

void CodeIndex::reset(int bits) {
  entries_.assign(size_t{1} << bits, Entry{kEmpty, -1});
  mask_ = entries_.size() - 1;
  shift_ = 64 - bits;
  size_ = 0;
}

void CodeIndex::set(uint64_t code, int64_t local) {
  if (2 * (size_ + 1) > entries_.size()) {  // at most half full: short probes
    const std::vector<Entry> old = std::move(entries_);
    int bits = kLeastBits;
    while ((size_t{1} << bits) < 4 * (size_ + 1)) ++bits;
    reset(bits);
    for (const Entry& e : old)
      if (e.code != kEmpty) set(e.code, e.local);
  }
  size_t s = slotOf(code);
  while (entries_[s].code != kEmpty && entries_[s].code != code) s = (s + 1) & mask_;
  if (entries_[s].code == kEmpty) ++size_;
  entries_[s] = Entry{code, local};
}

void CodeIndex::assign(const std::vector<uint64_t>& codes) {
  int bits = kLeastBits;
  while ((size_t{1} << bits) < 2 * codes.size()) ++bits;
  reset(bits);
  for (size_t k = 0; k < codes.size(); ++k) set(codes[k], static_cast<int64_t>(k));
}

}  // namespace rangefuse::internal
