#include "rangefuse/fuse/ScanLoader.h"

#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/parallel/FaultInjection.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

template <class T>
void packVector(std::vector<char>& buf, const std::vector<T>& v) {
  const uint64_t n = v.size();
  mpi::pack(buf, &n, 1);
  mpi::pack(buf, v.data(), n);
}

template <class T>
void unpackVector(const std::vector<char>& buf, size_t& pos, std::vector<T>& v) {
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  v.resize(n);
  mpi::unpack(buf, pos, v.data(), n);
}

void packScan(std::vector<char>& buf, uint64_t index, const PrismScan& s) {
  mpi::pack(buf, &index, 1);
  packVector(buf, s.surface.points);
  packVector(buf, s.surface.normals);
  packVector(buf, s.surface.confidence);
  packVector(buf, s.surface.triangles);
  packVector(buf, s.limits);
}

uint64_t unpackScan(const std::vector<char>& buf, size_t& pos, PrismScan& s) {
  uint64_t index;
  mpi::unpack(buf, pos, &index, 1);
  unpackVector(buf, pos, s.surface.points);
  unpackVector(buf, pos, s.surface.normals);
  unpackVector(buf, pos, s.surface.confidence);
  unpackVector(buf, pos, s.surface.triangles);
  unpackVector(buf, pos, s.limits);
  return index;
}

}  // namespace

IndexedScans loadScanShare(const io::ConfFile& conf, const SurfaceOptions& options,
                           const InputLimits& limits, double eps, int rank, int ranks) {
  IndexedScans mine;
  for (size_t i = rank; i < conf.scans.size(); i += ranks) {
    const io::ConfScan& c = conf.scans[i];
    PrismScan s;
    faultPoint("read", c.path);
    s.surface = buildScanSurface(io::readRangeGridPly(c.path, limits), Pose{}, options);
    s.limits = computePrismLimits(s.surface, eps);
    mine.emplace_back(i, std::move(s));
  }
  return mine;
}

std::vector<PrismScan> shareScans(const IndexedScans& mine, size_t total, MPI_Comm comm) {
  std::vector<char> buf;
  for (const auto& [i, s] : mine) packScan(buf, i, s);
  std::vector<PrismScan> all(total);
  for (const auto& part : mpi::allgatherBytes(buf, comm))
    for (size_t pos = 0; pos < part.size();) {
      PrismScan s;
      uint64_t i = unpackScan(part, pos, s);
      all[i] = std::move(s);
    }
  return all;
}

}  // namespace rangefuse

namespace rangefuse {

PrismScan placeScan(const PrismScan& local, const Pose& pose) {
  PrismScan s = local;
  for (auto& p : s.surface.points) p = pose.apply(p);
  for (auto& n : s.surface.normals) n = pose.rotate(n);
  return s;
}

}  // namespace rangefuse
