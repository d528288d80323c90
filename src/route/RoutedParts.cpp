#include "rangefuse/route/RoutedParts.h"

#include <algorithm>

#include "PartPacking.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/route/ScanLoader.h"

namespace rangefuse {

void RoutedParts::keep(uint64_t entry, PrismScan&& part) {
  bytes_ += scanBytes(part);
  parts_.push_back({entry, npos, loose_.size(), scanBytes(part)});
  loose_.push_back(std::move(part));
}

void RoutedParts::keepBytes(uint64_t entry, std::vector<char>&& bytes) {
  bytes.shrink_to_fit();  // packing reserves what a part takes at most
  parts_.push_back({entry, buffers_.size(), 0, bytes.size()});
  hold(std::move(bytes), 1);
}

void RoutedParts::receive(std::vector<char>&& bytes) {
  if (bytes.empty()) return;
  size_t count = 0;
  for (size_t pos = 0; pos < bytes.size(); ++count) {
    const size_t at = pos;
    const uint64_t entry = internal::skipPart(bytes, pos);
    parts_.push_back({entry, buffers_.size(), at, pos - at});
  }
  bytes.shrink_to_fit();  // a rank's buffer grew by doubling as it was packed
  hold(std::move(bytes), count);
}

void RoutedParts::hold(std::vector<char>&& bytes, size_t parts) {
  bytes_ += bytes.size();
  untaken_.push_back(parts);
  buffers_.push_back(std::move(bytes));
}

void RoutedParts::sortByEntry() {
  std::stable_sort(parts_.begin(), parts_.end(),
                   [](const Part& a, const Part& b) { return a.entry < b.entry; });
}

PrismScan RoutedParts::unpack(size_t k) {
  const Part& p = parts_[k];
  if (p.buffer == npos) return std::move(loose_[p.offset]);
  PrismScan part;
  size_t pos = p.offset;
  internal::unpackPart(buffers_[p.buffer], pos, part);
  return part;
}

void RoutedParts::release(size_t k) {
  const Part& p = parts_[k];
  if (p.buffer == npos) {
    bytes_ -= p.bytes;
  } else if (--untaken_[p.buffer] == 0) {
    bytes_ -= buffers_[p.buffer].size();
    std::vector<char>().swap(buffers_[p.buffer]);
  }
}

PrismScan RoutedParts::take(size_t k) {
  PrismScan part = unpack(k);
  release(k);
  return part;
}

IndexedScans RoutedParts::take(size_t first, size_t end, int threads) {
  IndexedScans out(end - first);
  parallelFor(out.size(), threads, [&](size_t j) {
    out[j] = {parts_[first + j].entry, unpack(first + j)};
  });
  for (size_t k = first; k < end; ++k) release(k);
  return out;
}

IndexedScans RoutedParts::takeAll() {
  IndexedScans all;
  all.reserve(parts_.size());
  for (size_t k = 0; k < parts_.size(); ++k) all.emplace_back(parts_[k].entry, take(k));
  return all;
}

}  // namespace rangefuse
