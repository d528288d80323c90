#include "FollowedFolder.h"

#include <chrono>
#include <filesystem>
#include <thread>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/HeldScans.h"

namespace rangefuse::internal {

namespace {

constexpr double kPollSeconds = 0.1;
constexpr const char* kStopFile = "STOP";

/// Frames the list of `scans` holds now, or 0 while it cannot be read (a folder still empty, a
/// list being written).
size_t listed(const ReadSettings& o) {
  try {
    return io::readScanList(o.scans, o.limits, o.source).scans.size();
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace

FollowedFolder::FollowedFolder(const ReadSettings& read, double timeout, MPI_Comm comm)
    : o_(read), timeout_(timeout), comm_(comm), seenAt_(MPI_Wtime()) {}

size_t FollowedFolder::waitForFrames(size_t have) {
  uint64_t take[2] = {0, 0};  // frames to take, recording stopped
  if (mpi::rank(comm_) == 0) {
    const std::filesystem::path stop = std::filesystem::path(o_.scans) / kStopFile;
    for (;;) {
      const size_t n = listed(o_);
      if (n > seen_) seen_ = n, seenAt_ = MPI_Wtime();  // the recording goes on
      const bool stopping =
          stopped_ || std::filesystem::exists(stop) || MPI_Wtime() - seenAt_ > timeout_;
      if (stopping) {
        take[0] = n, take[1] = 1;
        break;
      }
      if (n > have + 1) {
        take[0] = n - 1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::duration<double>(kPollSeconds));
    }
  }
  MPI_Bcast(take, 2, MPI_UINT64_T, 0, comm_);
  stopped_ = take[1] != 0;
  return take[0];
}

io::ConfFile FollowedFolder::first() {
  const size_t take = waitForFrames(1);
  io::ConfFile conf;
  mpi::collectivelyOrThrow(comm_, [&] {
    if (take == 0)
      throw InputError(o_.scans + ": --follow: no frames appeared within --follow-timeout " +
                       std::to_string(timeout_) + " s");
    conf = io::readScanList(o_.scans, o_.limits, o_.source);
    if (conf.posed)
      throw InputError(o_.scans +
                       ": --follow reads a stream being recorded, which has no trajectory yet");
    if (conf.scans.size() < take)
      throw InputError(o_.scans + ": --follow: this rank sees " +
                       std::to_string(conf.scans.size()) + " frames, rank 0 " +
                       std::to_string(take));
    conf.scans.resize(take);
  });
  return conf;
}

bool FollowedFolder::more(LoadedScans& scans) {
  const size_t have = scans.names.size();
  const size_t take = waitForFrames(have);
  if (take <= have) return false;
  std::vector<io::ConfScan> fresh;
  mpi::collectivelyOrThrow(comm_, [&] {
    io::ConfFile conf = io::readScanList(o_.scans, o_.limits, o_.source);
    if (conf.scans.size() < take)
      throw InputError(o_.scans + ": --follow: this rank sees " +
                       std::to_string(conf.scans.size()) + " frames, rank 0 " +
                       std::to_string(take));
    fresh.assign(conf.scans.begin() + static_cast<std::ptrdiff_t>(have),
                 conf.scans.begin() + static_cast<std::ptrdiff_t>(take));
  });
  std::vector<int> readers;
  for (size_t i = have; i < take; ++i) {
    readers.push_back(readerOf(i, mpi::size(comm_)));
    scans.readers.push_back(readers.back());
    scans.names.push_back(fresh[i - have].name);
    scans.paths.push_back(fresh[i - have].path);
    scans.times.push_back(fresh[i - have].time);
  }
  scans.held->append(fresh, readers);
  return true;
}

}  // namespace rangefuse::internal
