#include "rangefuse/track/PixelMotion.h"

#include "rangefuse/io/DepthPng.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {
namespace {

/// Half a turn about x: between the scan frame (looking toward -z) and the camera's.
Pose flipped(const Pose& p) {
  const Eigen::Matrix3d F = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return Pose{F * p.R * F, F * p.t};
}

std::shared_ptr<const io::ConfFile> listOf(const ReadSettings& read) {
  if (read.list) return read.list;
  return std::make_shared<const io::ConfFile>(
      io::readScanList(read.scans, read.limits, read.source));
}

}  // namespace

PixelMotion::PixelMotion(const ReadSettings& read, double voxel, MPI_Comm comm)
    : comm_(comm), read_(read), list_(listOf(read)) {
  settings_.maxDistance = 10 * voxel;
  settings_.huber = voxel;
}

Pose PixelMotion::operator()(size_t last, size_t next, const Pose& guess) {
  const int root = 0;
  double packed[12];
  mpi::collectivelyOrThrow(comm_, [&] {
    if (mpi::rank(comm_) != root) return;
    const Pose found =
        flipped(alignFrames(depthMap(last), depthMap(next), flipped(guess), settings_).motion);
    std::copy(found.R.data(), found.R.data() + 9, packed);
    std::copy(found.t.data(), found.t.data() + 3, packed + 9);
  });
  MPI_Bcast(packed, 12, MPI_DOUBLE, root, comm_);
  Pose out;
  out.R = Eigen::Map<const Eigen::Matrix3d>(packed);
  out.t = Eigen::Vector3d(packed[9], packed[10], packed[11]);
  return out;
}

const DepthMap& PixelMotion::depthMap(size_t i) {
  for (auto& [index, map] : cache_)
    if (index == i) return map;
  if (i >= list_->scans.size()) list_ = listOf(read_);
  const io::ConfScan& scan = list_->scans[i];
  const io::DepthCamera& c = *scan.depth;
  const io::DepthImage image =
      scan.memory ? scan.memory->depth : io::readDepthPng(scan.path, read_.limits.maxGridCells);
  DepthMap map{image.width, image.height, c.fx, c.fy, c.cx, c.cy, {}};
  map.depth.resize(image.counts.size());
  for (size_t k = 0; k < image.counts.size(); ++k) {
    const double d = image.counts[k] * c.unit;
    map.depth[k] = c.depthMax > 0 && d > c.depthMax ? 0.0f : static_cast<float>(d);
  }
  cache_[next_] = {i, std::move(map)};
  next_ = 1 - next_;
  return cache_[1 - next_].second;
}

}  // namespace rangefuse::internal
