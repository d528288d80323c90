// The checkpoint entry: HDF5 itself is not ours to harden, so the fuzzer chooses the content
// of a well-formed HDF5 file (attributes, dataset shapes, types, counts, metadata) and our
// loader has to refuse every wrong one cleanly.
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "FuzzEntries.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Digest.h"
#include "rangefuse/parallelio/Checkpoint.h"

namespace rangefuse::fuzz {
namespace {

/// Draws choices from the fuzzer's bytes; zeros once they run out.
class Chooser {
 public:
  explicit Chooser(const std::string& bytes) : bytes_(bytes) {}
  uint8_t byte() { return pos_ < bytes_.size() ? static_cast<uint8_t>(bytes_[pos_++]) : 0; }
  uint32_t u32() {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = v << 8 | byte();
    return v;
  }
  uint64_t u64() { return uint64_t(u32()) << 32 | u32(); }
  bool flag() { return byte() & 1; }
  std::string text(size_t maxLength) {
    std::string s(byte() % (maxLength + 1), '\0');
    for (char& ch : s) ch = static_cast<char>(byte());
    return s;
  }
  /// Mostly interesting values, sometimes any bit pattern.
  double number() {
    static const double kValues[] = {0,
                                     1,
                                     -1,
                                     0.5,
                                     1e-3,
                                     2,
                                     8,
                                     64,
                                     65,
                                     1e9,
                                     1e300,
                                     -1e300,
                                     std::numeric_limits<double>::infinity(),
                                     std::nan("")};
    const uint8_t k = byte();
    if (k < sizeof(kValues) / sizeof(kValues[0])) return kValues[k];
    double v;
    const uint64_t bits = u64();
    std::memcpy(&v, &bits, sizeof(v));
    return v;
  }

 private:
  const std::string& bytes_;
  size_t pos_ = 0;
};

/// A scalar attribute of `type`.
void attribute(hid_t obj, const char* name, hid_t type, const void* value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, type, value);
  H5Aclose(attr);
  H5Sclose(space);
}

/// A fixed-length string attribute (HDF5 refuses zero-length string types: one NUL then).
void stringAttribute(hid_t obj, const char* name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.empty() ? 1 : value.size());
  std::string padded = value.empty() ? std::string(1, '\0') : value;
  attribute(obj, name, type, padded.data());
  H5Tclose(type);
}

/// A dataset of `type` with the given dims; `data` (may be null: left unwritten, as a file
/// that declares more than it stores) is converted from `memType`.
void dataset(hid_t file, const char* name, hid_t type, const std::vector<hsize_t>& dims,
             hid_t memType, const void* data) {
  hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  hid_t set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (set >= 0 && data) H5Dwrite(set, memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  if (set >= 0) H5Dclose(set);
  H5Sclose(space);
}

/// Checkpoint metadata shaped like the real thing, with chosen values and defects.
nlohmann::json chosenMeta(Chooser& c, bool hasField, int& brick) {
  using nlohmann::json;
  json j;
  j["parameters"] = c.flag() ? json{{"voxel", c.number()}} : json(c.number());
  const int scans = c.byte() % 4;
  j["scans"] = json::array();
  j["scan_hashes"] = json::array();
  j["poses"] = json::array();
  for (int i = 0; i < scans + (c.flag() ? 1 : 0); ++i) j["scans"].push_back(c.text(8));
  for (int i = 0; i < scans; ++i) j["scan_hashes"].push_back(c.text(16));
  for (int i = 0; i < scans; ++i) {
    std::vector<double> pose = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    if (c.flag()) pose[c.byte() % 12] = c.number();
    if (c.flag()) pose.resize(c.byte() % 14);
    j["poses"].push_back(pose);
  }
  j["progress"] = c.flag() ? json{{"stage", c.text(8)}} : json::object();
  j["has_field"] = hasField;
  brick = c.flag() ? int(c.byte() % 70) - 2 : 4;
  j["grid"] = {{"origin", {c.number(), c.number(), c.number()}},
               {"voxel", c.flag() ? c.number() : 0.001},
               {"brick", brick}};
  if (c.flag()) j.erase(c.flag() ? "poses" : "grid");
  return j;
}

/// The format and version attributes and the metadata dataset, each possibly wrong or absent.
void writeMeta(hid_t file, Chooser& c, uint32_t flags, int& brick) {
  if (!(flags & 1))
    stringAttribute(file, "format", flags & 2 ? c.text(24) : "rangefuse-checkpoint");
  if (!(flags & 4)) {
    const int version = flags & 16 ? static_cast<int>(c.u32()) : io::kCheckpointVersion;
    if (flags & 8)
      stringAttribute(file, "version", c.text(4));
    else
      attribute(file, "version", H5T_NATIVE_INT, &version);
  }
  const std::string json =
      flags & 32 ? c.text(200)
                 : chosenMeta(c, flags & 64, brick)
                       .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (flags & 128) return;
  const hsize_t declared = flags & 512 ? c.u32() : json.size();
  const bool written = declared == json.size() && !json.empty();
  dataset(file, "meta", flags & 256 ? H5T_NATIVE_INT : H5T_NATIVE_CHAR,
          {flags & 0x10000 ? declared : std::max<hsize_t>(declared, 1)}, H5T_NATIVE_CHAR,
          written ? json.data() : nullptr);
  const hid_t set = H5Dopen2(file, "meta", H5P_DEFAULT);
  // The checksum of what was meant, right or (flag) wrong, so the checks behind it are reached.
  if (set >= 0 && !(flags & 0x2000000)) {
    const uint64_t digest = io::fnv1a64(json.data(), json.size()) + (flags & 0x1000000 ? 1 : 0);
    attribute(set, "fnv1a64", H5T_NATIVE_UINT64, &digest);
  }
  if (set >= 0) H5Dclose(set);
}

/// field_codes, field_work and field_sums with chosen counts, shapes and types.
void writeField(hid_t file, Chooser& c, uint32_t flags, int brick) {
  const hsize_t nb = c.byte() % 9;
  std::vector<uint64_t> codes(nb), work(nb, 1);
  uint64_t code = 0;
  for (auto& v : codes) v = flags & 1024 ? c.u64() : (code += 1 + c.byte() % 5);
  const hsize_t b = brick > 0 ? brick : 1;
  const hsize_t per = b * b * b * 6;
  const hsize_t rows = flags & 4096 ? c.byte() % 9 : nb;
  const hsize_t cols = flags & 8192 ? c.u32() % 100000 : per;
  if (!(flags & 0x20000))
    dataset(file, "field_codes", flags & 2048 ? H5T_NATIVE_DOUBLE : H5T_NATIVE_UINT64,
            {std::max<hsize_t>(nb, 1)}, H5T_NATIVE_UINT64, nb ? codes.data() : nullptr);
  if (!(flags & 0x40000))
    dataset(file, "field_work", H5T_NATIVE_UINT64,
            {std::max<hsize_t>(nb, 1) + (flags & 0x80000 ? 1 : 0)}, H5T_NATIVE_UINT64, nullptr);
  if (!(flags & 0x100000)) {
    const bool small = rows * cols <= (1u << 20);
    std::vector<float> sums(small ? rows * cols : 0, flags & 0x200000 ? NAN : 1.0f);
    dataset(file, "field_sums", flags & 0x400000 ? H5T_NATIVE_DOUBLE : H5T_NATIVE_FLOAT,
            flags & 0x800000
                ? std::vector<hsize_t>{std::max<hsize_t>(rows, 1)}
                : std::vector<hsize_t>{std::max<hsize_t>(rows, 1), std::max<hsize_t>(cols, 1)},
            H5T_NATIVE_FLOAT, small && rows && cols && !(flags & 0x800000) ? sums.data() : nullptr);
  }
}

/// One file per process and rank: the regression test replays on 2 ranks at once.
std::string tempPath() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return "/tmp/rangefuse-fuzz-" + std::to_string(getpid()) + "-" + std::to_string(rank) + ".h5";
}

}  // namespace

void checkpoint(const std::string& bytes) {
  Chooser c(bytes);
  const std::string path = tempPath();
  const uint32_t flags = c.u32();
  int brick = 4;
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  writeMeta(file, c, flags, brick);
  writeField(file, c, flags, brick);
  H5Fclose(file);
  try {
    const io::CheckpointMeta meta = io::readCheckpointMeta(path, MPI_COMM_SELF, fuzzLimits());
    BrickLayout layout;
    if (meta.hasField) io::readCheckpointField(path, meta, layout, MPI_COMM_SELF);
  } catch (const InputError&) {
  }
  std::remove(path.c_str());
}

}  // namespace rangefuse::fuzz
