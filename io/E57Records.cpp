#include "E57Records.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "rangefuse/core/Error.h"

namespace rangefuse::io::internal {
namespace {

uint16_t le16(const uint8_t* p) {
  return static_cast<uint16_t>(p[0] | p[1] << 8);
}

uint64_t le64(const uint8_t* p) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
#else
  uint64_t v = 0;
  for (int k = 7; k >= 0; --k) v = v << 8 | p[k];
  return v;
#endif
}

/// One field's byte stream: the bytes received and not yet decoded, and the bit to start at.
class FieldStream {
 public:
  explicit FieldStream(const E57Field& field) : field_(field), bits_(field.bits()) {}

  void append(const uint8_t* p, size_t n) {
    const size_t used = bit_ / 8;  // whole bytes already decoded
    bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(used));
    bit_ -= 8 * used;
    bytes_.insert(bytes_.end(), p, p + n);
  }

  /// Whole values waiting (unbounded for a constant field, which stores nothing).
  size_t available() const {
    if (bits_ == 0) return std::numeric_limits<size_t>::max();
    return (8 * bytes_.size() - bit_) / static_cast<size_t>(bits_);
  }

  /// Decodes n values into `out`, or skips them when out is null.
  void take(size_t n, std::vector<double>* out) {
    if (!out) {
      bit_ += n * static_cast<size_t>(bits_);
      return;
    }
    out->reserve(out->size() + n);
    for (size_t i = 0; i < n; ++i) out->push_back(next());
  }

 private:
  double next() {
    using Kind = E57Field::Kind;
    if (field_.kind == Kind::single || field_.kind == Kind::double_) {
      const uint8_t* p = bytes_.data() + bit_ / 8;
      bit_ += static_cast<size_t>(bits_);
      if (field_.kind == Kind::double_) {
        const uint64_t u = le64(p);
        double d;
        std::memcpy(&d, &u, 8);
        return d;
      }
      const uint32_t u =
          uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
      float f;
      std::memcpy(&f, &u, 4);
      return f;
    }
    const uint64_t raw = rawBits();
    const auto value = static_cast<int64_t>(static_cast<uint64_t>(field_.minimum) + raw);
    return field_.kind == Kind::scaledInteger ? double(value) * field_.scale + field_.offset
                                              : double(value);
  }

  /// The next bits_ bits, least significant first.
  uint64_t rawBits() {
    if (bits_ == 0) return 0;
    const size_t byte = bit_ / 8;
    if (bits_ <= 56 && byte + 8 <= bytes_.size()) {
      // Eight bytes from the value's first: it lies within them whatever its first bit.
      const uint64_t word = le64(bytes_.data() + byte) >> (bit_ % 8);
      bit_ += static_cast<size_t>(bits_);
      return word & ((uint64_t{1} << bits_) - 1);
    }
    uint64_t v = 0;
    int got = 0;
    while (got < bits_) {
      const size_t byte = bit_ / 8;
      const int shift = static_cast<int>(bit_ % 8);
      const int take = std::min(8 - shift, bits_ - got);
      v |= (uint64_t(bytes_[byte] >> shift) & ((1u << take) - 1)) << got;
      got += take;
      bit_ += static_cast<size_t>(take);
    }
    return v;
  }

  const E57Field& field_;
  int bits_;
  std::vector<uint8_t> bytes_;
  size_t bit_ = 0;
};

[[noreturn]] void bad(const E57Pages& pages, const E57Scan& scan, uint64_t logical,
                      const std::string& what) {
  throw InputError(pages.path() + ": " + scan.name + ": byte " +
                   std::to_string(e57Physical(logical)) + ": " + what);
}

}  // namespace

void decodeE57Records(E57Pages& pages, const E57Scan& scan, const std::vector<bool>& wanted,
                      const std::function<void(const E57Records&)>& use) {
  const uint64_t at = e57Logical(scan.section);
  uint8_t h[32];
  pages.read(at, h, 32);
  const uint64_t length = le64(h + 8), data = e57Logical(le64(h + 16));
  if (h[0] != 1)
    bad(pages, scan, at, "not a compressed vector section (id " + std::to_string(h[0]) + ")");
  if (length < 32 || at + length > pages.logicalSize() || data < at + 32 || data > at + length)
    bad(pages, scan, at, "the section's length or data offset lies outside the file");
  const uint64_t end = at + length;
  std::vector<FieldStream> streams;
  for (const E57Field& f : scan.fields) streams.emplace_back(f);
  bool counted = false;  // does any field store bits (so that packets tell how many records)?
  for (const E57Field& f : scan.fields) counted |= f.bits() > 0;
  E57Records chunk;
  chunk.values.resize(scan.fields.size());
  uint64_t done = 0;
  std::vector<uint8_t> packet(65536);
  for (uint64_t pos = data; done < scan.records;) {
    if (pos + 4 > end)
      bad(pages, scan, pos,
          "the points end after " + std::to_string(done) + " of " + std::to_string(scan.records) +
              " records (the section is cut short)");
    pages.read(pos, packet.data(), 4);
    const size_t size = size_t(le16(packet.data() + 2)) + 1;
    if (pos + size > end) bad(pages, scan, pos, "a packet runs past the end of its section");
    const uint8_t type = packet[0];
    if (type > 2) bad(pages, scan, pos, "unknown packet type " + std::to_string(type));
    if (type == 1) {
      pages.read(pos, packet.data(), size);
      const size_t streamsHere = le16(packet.data() + 4);
      if (streamsHere != streams.size())
        bad(pages, scan, pos,
            "a data packet with " + std::to_string(streamsHere) + " byte streams for " +
                std::to_string(streams.size()) + " prototype fields");
      size_t offset = 6 + 2 * streamsHere;
      for (size_t k = 0; k < streamsHere; ++k) {
        const size_t n = le16(packet.data() + 6 + 2 * k);
        if (offset + n > size) bad(pages, scan, pos, "byte streams longer than their packet");
        streams[k].append(packet.data() + offset, n);
        offset += n;
      }
      size_t ready = counted ? std::numeric_limits<size_t>::max() : size_t(scan.records - done);
      for (const FieldStream& s : streams) ready = std::min(ready, s.available());
      ready = static_cast<size_t>(std::min<uint64_t>(ready, scan.records - done));
      for (auto& v : chunk.values) v.clear();
      for (size_t k = 0; k < streams.size(); ++k)
        streams[k].take(ready, wanted[k] ? &chunk.values[k] : nullptr);
      chunk.count = ready;
      done += ready;
      if (ready > 0) use(chunk);
    }
    pos += size;
  }
}

}  // namespace rangefuse::io::internal
