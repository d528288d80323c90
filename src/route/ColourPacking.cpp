#include "ColourPacking.h"

#include <cstring>
#include <limits>

#include "BitMask.h"
#include "PickedBytes.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {
namespace {

/// Writes the form and the length; false (nothing more to write) for an empty vector.
bool packHead(std::vector<char>& buf, Form form, uint64_t n) {
  mpi::pack(buf, &form, 1);
  mpi::pack(buf, &n, 1);
  return n > 0;
}

std::pair<Form, uint64_t> unpackHead(const std::vector<char>& buf, size_t& pos) {
  Form form;
  uint64_t n;
  mpi::unpack(buf, pos, &form, 1);
  mpi::unpack(buf, pos, &n, 1);
  return {form, n};
}

bool isNarrowBlock(const std::array<int32_t, 2>& b) {
  constexpr int32_t most = std::numeric_limits<uint16_t>::max();
  return b[0] >= 0 && b[0] <= most && b[1] >= 0 && b[1] <= most;
}

bool isNarrowTexel(const Texel& t) {
  return t[3] == 255 || (t[0] | t[1] | t[2] | t[3]) == 0;
}

/// Whether the eight texels from t on are all sampled.
bool allSampled(const Texel* t) {
  uint8_t alpha = 255;
  for (int b = 0; b < 8; ++b) alpha &= t[b][3];
  return alpha == 255;
}

}  // namespace

bool byteColour(const Colour& c, uint8_t bytes[3]) {
  const std::array<float, 256>& channel = kByteChannels;
  for (int k = 0; k < 3; ++k) {
    if (!(c[k] >= 0 && c[k] <= 1)) return false;  // NaN too
    // The nearest byte, or one that fails the test below: the test is what keeps it exact.
    bytes[k] = static_cast<uint8_t>(c[k] * 255 + 0.5f);
    if (std::memcmp(&channel[bytes[k]], &c[k], sizeof(float)) != 0) return false;  // -0 is not 0
  }
  return true;
}

void packColours(std::vector<char>& buf, const std::vector<Colour>& v,
                 const std::vector<uint32_t>& pick) {
  const uint64_t n = v.empty() ? 0 : pick.size();
  const size_t head = buf.size();
  packHead(buf, Form::narrow, n);
  char* out = grow(buf, 3 * n);
  for (size_t k = 0; k < n; ++k, out += 3)
    if (!byteColour(v[pick[k]], reinterpret_cast<uint8_t*>(out))) {
      buf.resize(head);  // one is not a byte colour: all go as they are
      packHead(buf, Form::asIs, n);
      return appendPicked(buf, v, pick);
    }
}

void unpackColours(const std::vector<char>& buf, size_t& pos, std::vector<Colour>& v) {
  const auto [form, n] = unpackHead(buf, pos);
  v.resize(n);
  if (form == Form::asIs) return mpi::unpack(buf, pos, v.data(), n);
  const std::array<float, 256>& channel = kByteChannels;
  const auto* in = reinterpret_cast<const uint8_t*>(buf.data() + pos);
  for (Colour& c : v) c = {channel[in[0]], channel[in[1]], channel[in[2]]}, in += 3;
  pos += 3 * n;
}

void skipColours(const std::vector<char>& buf, size_t& pos) {
  const auto [form, n] = unpackHead(buf, pos);
  pos += n * (form == Form::narrow ? 3 : sizeof(Colour));
}

void packBlocks(std::vector<char>& buf, const std::vector<std::array<int32_t, 2>>& v,
                const std::vector<uint32_t>& pick) {
  const uint64_t n = v.empty() ? 0 : pick.size();
  bool narrow = true;
  for (size_t k = 0; k < n && narrow; ++k) narrow = isNarrowBlock(v[pick[k]]);
  if (!packHead(buf, narrow ? Form::narrow : Form::asIs, n)) return;
  if (!narrow) return appendPicked(buf, v, pick);
  char* out = grow(buf, n * 2 * sizeof(uint16_t));
  for (uint32_t i : pick) {
    const uint16_t b[2] = {uint16_t(v[i][0]), uint16_t(v[i][1])};
    std::memcpy(out, b, sizeof b), out += sizeof b;
  }
}

void unpackBlocks(const std::vector<char>& buf, size_t& pos,
                  std::vector<std::array<int32_t, 2>>& v) {
  const auto [form, n] = unpackHead(buf, pos);
  v.resize(n);
  if (form == Form::asIs) return mpi::unpack(buf, pos, v.data(), n);
  const char* in = buf.data() + pos;
  for (auto& block : v) {
    uint16_t b[2];
    std::memcpy(b, in, sizeof b), in += sizeof b;
    block = {b[0], b[1]};
  }
  pos += n * 2 * sizeof(uint16_t);
}

void skipBlocks(const std::vector<char>& buf, size_t& pos) {
  const auto [form, n] = unpackHead(buf, pos);
  pos += n * (form == Form::narrow ? 2 * sizeof(uint16_t) : 2 * sizeof(int32_t));
}

void packTexelCells(std::vector<char>& buf, const std::vector<Texel>& v) {
  const uint64_t n = v.size();
  const size_t head = buf.size();
  if (!packHead(buf, Form::narrow, n)) return;
  // Written at once, as if every texel were narrow, and cut to the bytes used.
  const size_t at = buf.size();
  auto* mask = reinterpret_cast<uint8_t*>(grow(buf, maskBytes(n) + 3 * n));
  uint8_t* out = mask + maskBytes(n);
  const Texel* in = v.data();  // pointers of its own: stores through `out` alias nothing
  for (size_t k = 0; k < n; k += 8) {
    if (k + 8 <= n && allSampled(in + k)) {  // most often: eight texels' 3 bytes in a row
      // 4 bytes a texel: the next one overwrites the alpha each leaves.
      for (size_t b = 0; b < 7; ++b) std::memcpy(out + 3 * b, in[k + b].data(), 4);
      std::memcpy(out + 21, in[k + 7].data(), 3);
      out += 24;
      mask[k / 8] = 0xff;
      continue;
    }
    uint8_t bits = 0;
    for (size_t b = 0; b < std::min<size_t>(8, n - k); ++b) {
      const Texel& t = in[k + b];
      if (t[3] == 255) {
        bits = uint8_t(bits | 1 << b);
        out[0] = t[0], out[1] = t[1], out[2] = t[2], out += 3;
      } else if (!isNarrowTexel(t)) {  // neither sampled nor blank: all go as they are
        buf.resize(head);
        packHead(buf, Form::asIs, n);
        return mpi::pack(buf, v.data(), n);
      }
    }
    mask[k / 8] = bits;
  }
  buf.resize(at + size_t(out - mask));
}

void unpackTexelCells(const std::vector<char>& buf, size_t& pos, std::vector<Texel>& v) {
  const auto [form, n] = unpackHead(buf, pos);
  v.assign(n, Texel{0, 0, 0, 0});  // blank unless the mask says sampled
  if (form == Form::asIs) return mpi::unpack(buf, pos, v.data(), n);
  const char* mask = buf.data() + pos;
  const auto* in = reinterpret_cast<const uint8_t*>(mask + maskBytes(n));
  Texel* out = v.data();
  for (size_t k = 0; k < n; k += 8) {
    const auto bits = uint8_t(mask[k / 8]);
    if (bits == 0xff && k + 8 <= n) {   // most often: eight sampled texels, without a branch
      for (size_t b = 0; b < 7; ++b) {  // 4 bytes read, the fourth the next texel's
        Texel t;
        std::memcpy(t.data(), in + 3 * b, 4);
        t[3] = 255;
        out[k + b] = t;
      }
      out[k + 7] = {in[21], in[22], in[23], 255};
      in += 24;
      continue;
    }
    for (size_t b = 0; b < std::min<size_t>(8, n - k); ++b)
      if (bitAt(mask, k + b)) out[k + b] = {in[0], in[1], in[2], 255}, in += 3;
  }
  pos = size_t(reinterpret_cast<const char*>(in) - buf.data());
}

void skipTexelCells(const std::vector<char>& buf, size_t& pos) {
  const auto [form, n] = unpackHead(buf, pos);
  pos += form == Form::narrow ? maskBytes(n) + 3 * setBits(buf.data() + pos, n) : n * sizeof(Texel);
}

}  // namespace rangefuse::internal
