#include "rangefuse/parallelio/Checkpoint.h"

#include <hdf5.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "Hdf5Writing.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/Digest.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse::io {
namespace {

using internal::accessList;
using internal::check;
using internal::createDataset;
using internal::Handle;
using internal::together;
using internal::writeRows;

static_assert(sizeof(VoxelSums) == 6 * sizeof(float), "checkpoint stores 6 floats a voxel");
constexpr const char* kFormat = "rangefuse-checkpoint";
constexpr const char* kDigest = "fnv1a64";  // checksum attribute of each dataset

nlohmann::json metaJson(const CheckpointMeta& m) {
  nlohmann::json poses = nlohmann::json::array();
  for (const Pose& p : m.poses) poses.push_back(poseNumbers(p));
  nlohmann::json j = {{"parameters", m.parameters},  {"scans", m.scanNames},
                      {"scan_hashes", m.scanHashes}, {"poses", poses},
                      {"progress", m.progress},      {"has_field", m.hasField}};
  if (m.hasField)
    j["grid"] = {{"origin", {m.grid.origin.x(), m.grid.origin.y(), m.grid.origin.z()}},
                 {"voxel", m.grid.voxel},
                 {"brick", m.grid.brick}};
  return j;
}

CheckpointMeta metaFrom(const nlohmann::json& j, int version) {
  CheckpointMeta m;
  m.version = version;
  m.parameters = j.at("parameters");
  m.scanNames = j.at("scans").get<std::vector<std::string>>();
  m.scanHashes = j.at("scan_hashes").get<std::vector<std::string>>();
  m.progress = j.at("progress");
  m.hasField = j.at("has_field").get<bool>();
  for (const auto& v : j.at("poses")) m.poses.push_back(poseFromNumbers(v));
  if (m.hasField) {
    const auto& g = j.at("grid");
    const auto o = g.at("origin").get<std::vector<double>>();
    if (o.size() != 3) throw std::runtime_error("grid origin needs 3 numbers");
    m.grid.origin = Eigen::Vector3d(o[0], o[1], o[2]);
    m.grid.voxel = g.at("voxel").get<double>();
    m.grid.brick = g.at("brick").get<int>();
    if (!m.grid.origin.allFinite() || !(m.grid.voxel > 0) || !std::isfinite(m.grid.voxel) ||
        m.grid.brick < 2 || m.grid.brick > 64)
      throw std::runtime_error("grid voxel or brick out of range");
  }
  if (m.scanNames.size() != m.scanHashes.size() || m.scanNames.size() != m.poses.size())
    throw std::runtime_error("scan names, hashes and poses differ in number");
  return m;
}

void writeAttributeInt(hid_t obj, const char* name, int value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name, H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  H5Awrite(attr, H5T_NATIVE_INT, &value);
}

void writeAttributeU64(hid_t obj, const char* name, uint64_t value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name, H5T_NATIVE_UINT64, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  H5Awrite(attr, H5T_NATIVE_UINT64, &value);
}

/// The checksum attribute of a dataset, or a refusal naming what lacks one.
uint64_t readDigest(hid_t obj, const char* dataset, const std::string& path) {
  uint64_t v = 0;
  bool ok = H5Aexists(obj, kDigest) > 0;
  if (ok) {
    Handle attr(H5Aopen(obj, kDigest, H5P_DEFAULT), H5Aclose);
    ok = attr.ok() && H5Aread(attr, H5T_NATIVE_UINT64, &v) >= 0;
  }
  check(ok, path, std::string("damaged: the checksum of ") + dataset + " is missing");
  return v;
}

/// Refuses data whose checksum differs from the one written beside it.
void verify(uint64_t stored, const void* data, size_t bytes, const std::string& path,
            const std::string& what) {
  check(fnv1a64(data, bytes) == stored, path,
        "damaged: " + what +
            " does not match its checksum (the file changed after it was "
            "written; resume from an earlier checkpoint or run again from the scans)");
}

/// Per brick, the checksum of its row of `values` (`perRow` values a brick).
template <class T>
std::vector<uint64_t> rowDigests(const T* values, size_t bricks, size_t perRow) {
  std::vector<uint64_t> d(bricks);
  for (size_t b = 0; b < bricks; ++b) d[b] = fnv1a64(values + b * perRow, perRow * sizeof(T));
  return d;
}

/// Per brick, the checksum of its voxel sums (6 floats a voxel).
std::vector<uint64_t> brickDigests(const float* sums, size_t bricks, size_t perBrick) {
  return rowDigests(sums, bricks, perBrick * 6);
}

/// Collective: the checksum of every rank's bytes joined in rank order, on every rank: each
/// rank folds its own into the sum of those before it and passes it on.
uint64_t chainedDigest(const void* data, size_t bytes, MPI_Comm comm) {
  uint64_t h = kFnvOffset;
  mpi::passAlong(
      &h, sizeof h, [&] { h = fnv1a64(data, bytes, h); }, comm);
  return h;
}

/// Collective: chainedDigest of `values`.
uint64_t chainedDigest(const std::vector<uint64_t>& values, MPI_Comm comm) {
  return chainedDigest(values.data(), values.size() * sizeof(uint64_t), comm);
}

void writeAttributeString(hid_t obj, const char* name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, value.size());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  H5Awrite(attr, type, value.data());
}

std::string readAttributeString(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) return "";
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  Handle type(H5Aget_type(attr), H5Tclose);
  if (H5Tget_class(type) != H5T_STRING) return "";
  std::string s(H5Tget_size(type), '\0');
  Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mem, s.size());
  if (H5Aread(attr, mem, s.data()) < 0) return "";
  return s;
}

int readAttributeInt(hid_t obj, const char* name, const std::string& path) {
  check(H5Aexists(obj, name) > 0, path, std::string("no '") + name + "' attribute");
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  int v = 0;
  check(H5Aread(attr, H5T_NATIVE_INT, &v) >= 0, path, std::string("cannot read '") + name + "'");
  return v;
}

/// Dimensions of a dataset, checking its rank.
std::vector<hsize_t> datasetDims(hid_t file, const char* name, int rank, const std::string& path) {
  check(H5Lexists(file, name, H5P_DEFAULT) > 0, path, std::string("no dataset ") + name);
  Handle set(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  Handle space(H5Dget_space(set), H5Sclose);
  check(H5Sget_simple_extent_ndims(space) == rank, path,
        std::string(name) + " has the wrong number of dimensions");
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

/// The checksum attribute of a named dataset.
uint64_t datasetDigest(hid_t file, const char* name, const std::string& path) {
  Handle set(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  check(set.ok(), path, std::string("cannot open ") + name);
  return readDigest(set, name, path);
}

template <class T>
std::vector<T> readRows(hid_t file, const char* name, hid_t type, hsize_t first, hsize_t count,
                        hsize_t cols, const std::string& path) {
  Handle set(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  check(set.ok(), path, std::string("cannot open ") + name);
  Handle space(H5Dget_space(set), H5Sclose);
  const hsize_t start[2] = {first, 0}, size[2] = {count, cols};
  std::vector<T> out(count * (cols ? cols : 1));
  if (count == 0) return out;
  H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, size, nullptr);
  Handle mem(H5Screate_simple(cols ? 2 : 1, size, nullptr), H5Sclose);
  check(H5Dread(set, type, mem, space, H5P_DEFAULT, out.data()) >= 0, path,
        std::string("cannot read ") + name + " (truncated?)");
  return out;
}

/// Per brick, the checksum of its voxel colours (3 16-bit channels a voxel).
std::vector<uint64_t> colourDigests(const uint16_t* colours, size_t bricks, size_t perBrick) {
  return rowDigests(colours, bricks, perBrick * 3);
}

/// The voxel colours beside the sums (field_colours, with field_colour_digests per brick), their
/// kind an attribute of the colours' dataset.
void writeColours(hid_t file, const BrickStore& store, const std::string& tmp, MPI_Comm comm) {
  const BrickLayout& l = store.layout();
  const hsize_t nb = l.totalBricks(), per = store.voxelsPerBrick();
  Handle colours = createDataset(file, "field_colours", H5T_NATIVE_UINT16, nb, per * 3, tmp, comm);
  Handle digests = createDataset(file, "field_colour_digests", H5T_NATIVE_UINT64, nb, 0, tmp, comm);
  const uint16_t* mine = reinterpret_cast<const uint16_t*>(store.colours().data());
  const std::vector<uint64_t> own = colourDigests(mine, store.brickCount(), per);
  writeAttributeString(colours, "kind", colourKindName(store.colourKind()));
  writeAttributeU64(digests, kDigest, chainedDigest(own, comm));
  const int r = mpi::rank(comm);
  const hsize_t first = l.globalStart[r], count = store.brickCount();
  writeRows(colours, H5T_NATIVE_UINT16, first, count, per * 3, mine, tmp, "field_colours", comm);
  writeRows(digests, H5T_NATIVE_UINT64, first, count, 0, own.data(), tmp, "field_colour_digests",
            comm);
}

/// The field's datasets, each with a checksum: codes and work whole, the voxel sums per brick
/// (field_digests, rank-count independent so that any partition can check its own bricks).
/// Every rank writes its own bricks' rows.
void writeField(hid_t file, const BrickStore& store, const std::string& tmp, MPI_Comm comm) {
  const BrickLayout& l = store.layout();
  const int r = mpi::rank(comm);
  const hsize_t nb = l.totalBricks(), per = store.voxelsPerBrick();
  const hsize_t first = l.globalStart[r], count = store.brickCount();
  const std::vector<uint64_t> ownCodes(l.codes.begin() + l.rankStart[r],
                                       l.codes.begin() + l.rankStart[r + 1]);
  const std::vector<uint64_t> ownWork(l.work.begin() + l.rankStart[r],
                                      l.work.begin() + l.rankStart[r + 1]);
  Handle codes = createDataset(file, "field_codes", H5T_NATIVE_UINT64, nb, 0, tmp, comm);
  Handle work = createDataset(file, "field_work", H5T_NATIVE_UINT64, nb, 0, tmp, comm);
  Handle sums = createDataset(file, "field_sums", H5T_NATIVE_FLOAT, nb, per * 6, tmp, comm);
  Handle digests = createDataset(file, "field_digests", H5T_NATIVE_UINT64, nb, 0, tmp, comm);
  const float* mine = reinterpret_cast<const float*>(store.sums().data());
  const std::vector<uint64_t> own = brickDigests(mine, store.brickCount(), per);
  writeAttributeU64(codes, kDigest, chainedDigest(ownCodes, comm));
  writeAttributeU64(work, kDigest, chainedDigest(ownWork, comm));
  writeAttributeU64(digests, kDigest, chainedDigest(own, comm));
  writeRows(codes, H5T_NATIVE_UINT64, first, count, 0, ownCodes.data(), tmp, "field_codes", comm);
  writeRows(work, H5T_NATIVE_UINT64, first, count, 0, ownWork.data(), tmp, "field_work", comm);
  writeRows(sums, H5T_NATIVE_FLOAT, first, count, per * 6, mine, tmp, "field_sums", comm);
  writeRows(digests, H5T_NATIVE_UINT64, first, count, 0, own.data(), tmp, "field_digests", comm);
  if (store.hasColour()) writeColours(file, store, tmp, comm);
}

void writeFile(const std::string& tmp, const CheckpointMeta& meta, const BrickStore* store,
               MPI_Comm comm) {
  Handle fapl = accessList(comm);
  errno = 0;
  Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose);
  together(file.ok(), tmp, "cannot create checkpoint file", comm);
  writeAttributeString(file, "format", kFormat);
  writeAttributeInt(file, "version", meta.version);
  {
    const std::string json = metaJson(meta).dump();
    const bool root = mpi::rank(comm) == 0;
    Handle metaSet = createDataset(file, "meta", H5T_NATIVE_CHAR, json.size(), 0, tmp, comm);
    writeAttributeU64(metaSet, kDigest, fnv1a64(json.data(), json.size()));
    writeRows(metaSet, H5T_NATIVE_CHAR, 0, root ? json.size() : 0, 0, json.data(), tmp, "meta",
              comm);
  }
  if (store) writeField(file, *store, tmp, comm);
  errno = 0;
  together(file.close() >= 0, tmp, "cannot finish writing (flush and close)", comm);
}

/// Bytes the checkpoint's datasets hold, for the message when a write fails.
uint64_t checkpointBytes(const CheckpointMeta& meta, const BrickStore* store) {
  uint64_t bytes = metaJson(meta).dump().size() + 4096;
  if (store)
    bytes += store->layout().totalBricks() *
             (3 * 8 + store->voxelsPerBrick() * (store->hasColour() ? 30 : 24));
  return bytes;
}

}  // namespace

void writeCheckpoint(const std::string& path, const CheckpointMeta& meta, const BrickStore* store,
                     MPI_Comm comm) {
  const std::string tmp = temporaryPath(path);
  const std::string cause =
      internal::agreeOnWrite(tmp, comm, [&] { writeFile(tmp, meta, store, comm); });
  if (!cause.empty()) {
    const int64_t free = freeBytes(tmp);
    const std::string space =
        free < 0 ? ""
                 : "; it needs about " + std::to_string(checkpointBytes(meta, store) >> 20) +
                       " MiB, " + std::to_string(free >> 20) + " MiB are free there";
    throw InputError(path + ": checkpoint not written: " + cause + space +
                     " (the previous checkpoint, if any, is unchanged)");
  }
  internal::renameIntoPlace(tmp, path, comm);
}

CheckpointMeta readCheckpointMeta(const std::string& path, MPI_Comm comm,
                                  const InputLimits& limits) {
  {
    std::ifstream probe(path);
    check(bool(probe), path, "cannot open checkpoint");
  }
  check(H5Fis_hdf5(path.c_str()) > 0, path, "not an HDF5 file (or truncated)");
  Handle fapl = accessList(comm);
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl), H5Fclose);
  check(file.ok(), path, "cannot open as HDF5 (corrupt or truncated)");
  check(readAttributeString(file, "format") == kFormat, path, "not a rangefuse checkpoint");
  const int version = readAttributeInt(file, "version", path);
  check(version <= kCheckpointVersion, path,
        "written by a newer rangefuse (format version " + std::to_string(version) +
            ", this one reads up to " + std::to_string(kCheckpointVersion) + ")");
  check(version == kCheckpointVersion, path,
        "format version " + std::to_string(version) +
            " has no checksums, so it cannot be trusted; run again from the scans");
  const std::vector<hsize_t> dims = datasetDims(file, "meta", 1, path);
  checkLimit(path, "metadata bytes", static_cast<double>(dims[0]), limits.maxElements,
             "max-elements");
  const std::vector<char> bytes =
      readRows<char>(file, "meta", H5T_NATIVE_CHAR, 0, dims[0], 0, path);
  {
    Handle set(H5Dopen2(file, "meta", H5P_DEFAULT), H5Dclose);
    verify(readDigest(set, "meta", path), bytes.data(), bytes.size(), path, "the metadata");
  }
  CheckpointMeta m;
  try {
    m = metaFrom(nlohmann::json::parse(std::string(bytes.begin(), bytes.end())), version);
  } catch (const nlohmann::json::exception&) {
    throw InputError(path + ": damaged metadata (not the JSON a checkpoint holds)");
  } catch (const std::exception& e) {
    throw InputError(path + ": damaged metadata: " + e.what());
  }
  if (m.hasField) {
    const hsize_t nb = datasetDims(file, "field_codes", 1, path)[0];
    check(datasetDims(file, "field_work", 1, path)[0] == nb, path,
          "field_work does not match field_codes");
    const auto s = datasetDims(file, "field_sums", 2, path);
    const hsize_t per = hsize_t(m.grid.brick) * m.grid.brick * m.grid.brick;
    check(s[0] == nb && s[1] == per * 6, path,
          "field_sums is " + std::to_string(s[0]) + " x " + std::to_string(s[1]) + ", expected " +
              std::to_string(nb) + " x " + std::to_string(per * 6));
    checkLimit(path, "field voxels", static_cast<double>(nb) * per, limits.maxVoxels, "max-voxels");
  }
  return m;
}

namespace {

/// Rows [first, first + count) of this rank's part when `rows` are cut in equal parts.
void sliceOf(hsize_t rows, MPI_Comm comm, hsize_t& first, hsize_t& count) {
  const hsize_t r = static_cast<hsize_t>(mpi::rank(comm)),
                n = static_cast<hsize_t>(mpi::size(comm));
  first = rows * r / n;
  count = rows * (r + 1) / n - first;
}

/// Collective: refuses a whole dataset, read in slices on the ranks, whose checksum differs
/// from the one written beside it.
void verifyChained(hid_t file, const char* name, const std::vector<uint64_t>& slice,
                   const std::string& path, const std::string& what, MPI_Comm comm) {
  const uint64_t got = chainedDigest(slice, comm);
  mpi::collectivelyOrThrow(comm, [&] {
    check(got == datasetDigest(file, name, path), path,
          "damaged: " + what +
              " does not match its checksum (the file changed after it was "
              "written; resume from an earlier checkpoint or run again from the scans)");
  });
}

/// Collective: this rank's slice of the brick list as (code, work) pairs, checked: checksums,
/// Morton order (across slices too), inside the lattice.
std::vector<std::pair<uint64_t, uint64_t>> readBrickSlice(hid_t file, const std::string& path,
                                                          const VoxelGrid& grid, MPI_Comm comm) {
  hsize_t nb = 0, first = 0, count = 0;
  std::vector<uint64_t> codes, work, digests;
  uint64_t before = 0;
  mpi::collectivelyOrThrow(comm, [&] {
    nb = datasetDims(file, "field_codes", 1, path)[0];
    check(datasetDims(file, "field_digests", 1, path)[0] == nb, path,
          "field_digests does not match field_codes");
    sliceOf(nb, comm, first, count);
    codes = readRows<uint64_t>(file, "field_codes", H5T_NATIVE_UINT64, first, count, 0, path);
    work = readRows<uint64_t>(file, "field_work", H5T_NATIVE_UINT64, first, count, 0, path);
    digests = readRows<uint64_t>(file, "field_digests", H5T_NATIVE_UINT64, first, count, 0, path);
    if (first > 0 && count > 0)
      before = readRows<uint64_t>(file, "field_codes", H5T_NATIVE_UINT64, first - 1, 1, 0, path)[0];
  });
  verifyChained(file, "field_codes", codes, path, "field_codes (the brick list)", comm);
  verifyChained(file, "field_work", work, path, "field_work", comm);
  verifyChained(file, "field_digests", digests, path, "field_digests (the checksums of the bricks)",
                comm);
  std::vector<std::pair<uint64_t, uint64_t>> pairs;
  mpi::collectivelyOrThrow(comm, [&] {
    for (size_t i = 0; i < codes.size(); ++i) {
      check((i == 0 ? first == 0 || before < codes[0] : codes[i - 1] < codes[i]), path,
            "field_codes are not in Morton order");
      // the mesher packs 20 bits of voxel index per axis
      check((int64_t(mortonDecode(codes[i]).maxCoeff()) + 1) * grid.brick <= (1 << 20), path,
            "field_codes hold a brick outside the lattice");
      pairs.emplace_back(codes[i], work[i]);
    }
  });
  return pairs;
}

/// Collective: the voxel colours, when the checkpoint has them (older ones and uncoloured
/// fields do not: the store is then left without colour).
void readColours(hid_t file, const std::string& path, const BrickLayout& layout, BrickStore& store,
                 MPI_Comm comm) {
  if (H5Lexists(file, "field_colours", H5P_DEFAULT) <= 0) return;
  const hsize_t nb = layout.totalBricks(), per = store.voxelsPerBrick();
  std::string kind;
  std::vector<uint64_t> slice;
  mpi::collectivelyOrThrow(comm, [&] {
    const auto dims = datasetDims(file, "field_colours", 2, path);
    check(dims[0] == nb && dims[1] == per * 3, path, "field_colours does not match field_codes");
    check(datasetDims(file, "field_colour_digests", 1, path)[0] == nb, path,
          "field_colour_digests does not match field_codes");
    Handle set(H5Dopen2(file, "field_colours", H5P_DEFAULT), H5Dclose);
    kind = readAttributeString(set, "kind");
    check(kind == "rgb" || kind == "intensity", path,
          "field_colours has kind '" + kind + "', not rgb or intensity");
    hsize_t first = 0, count = 0;
    sliceOf(nb, comm, first, count);
    slice =
        readRows<uint64_t>(file, "field_colour_digests", H5T_NATIVE_UINT64, first, count, 0, path);
  });
  verifyChained(file, "field_colour_digests", slice, path,
                "field_colour_digests (the checksums of the colours)", comm);
  mpi::collectivelyOrThrow(comm, [&] {
    const int r = mpi::rank(comm);
    const hsize_t first = layout.globalStart[r], count = store.brickCount();
    const std::vector<uint64_t> digests =
        readRows<uint64_t>(file, "field_colour_digests", H5T_NATIVE_UINT64, first, count, 0, path);
    const std::vector<uint16_t> colours =
        readRows<uint16_t>(file, "field_colours", H5T_NATIVE_UINT16, first, count, per * 3, path);
    const std::vector<uint64_t> got = colourDigests(colours.data(), count, per);
    for (size_t b = 0; b < got.size(); ++b)
      check(got[b] == digests[b], path,
            "damaged: the colours of brick " + std::to_string(first + b) +
                " (field_colours) do not match their checksum");
    store.enableColour(parseColourKind(kind, ColourKind::none));
    if (!colours.empty())
      std::memcpy(static_cast<void*>(store.colours().data()), colours.data(),
                  colours.size() * sizeof(uint16_t));
  });
}

}  // namespace

std::unique_ptr<BrickStore> readCheckpointField(const std::string& path, const CheckpointMeta& meta,
                                                BrickLayout& layout, MPI_Comm comm) {
  check(meta.hasField, path, "holds no field");
  Handle fapl = accessList(comm);
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl), H5Fclose);
  mpi::collectivelyOrThrow(
      comm, [&] { check(file.ok(), path, "cannot open as HDF5 (corrupt or truncated)"); });
  // Each rank checks a slice of the brick list; the bricks are then cut by work for this
  // number of ranks and each rank reads its own rows.
  layout = spreadSorted(readBrickSlice(file, path, meta.grid, comm), meta.grid, comm);
  auto store = std::make_unique<BrickStore>(layout, mpi::rank(comm));
  mpi::collectivelyOrThrow(comm, [&] {
    const int r = mpi::rank(comm);
    const hsize_t per = store->voxelsPerBrick(), first = layout.globalStart[r],
                  count = store->brickCount();
    const std::vector<float> sums =
        readRows<float>(file, "field_sums", H5T_NATIVE_FLOAT, first, count, per * 6, path);
    const std::vector<uint64_t> digests =
        readRows<uint64_t>(file, "field_digests", H5T_NATIVE_UINT64, first, count, 0, path);
    const std::vector<uint64_t> got = brickDigests(sums.data(), count, per);
    for (size_t b = 0; b < got.size(); ++b)
      check(got[b] == digests[b], path,
            "damaged: the voxel sums of brick " + std::to_string(first + b) +
                " (field_sums) do not match their checksum; resume from an earlier checkpoint or "
                "run again from the scans");
    if (!sums.empty())  // a rank may own no brick
      std::memcpy(static_cast<void*>(store->sums().data()), sums.data(),
                  sums.size() * sizeof(float));
  });
  readColours(file, path, layout, *store, comm);
  return store;
}

std::string fileHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  uint64_t h = kFnvOffset;
  char buf[1 << 16];
  while (in.read(buf, sizeof(buf)) || in.gcount() > 0)
    h = fnv1a64(buf, static_cast<size_t>(in.gcount()), h);
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

}  // namespace rangefuse::io
