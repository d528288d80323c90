// A temporary path that every rank of a test agrees on.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::test {

/// temp_dir/rangefuse-STEM-PID.EXT (NAME is STEM.EXT) with rank 0's PID, the same string on
/// every rank; the extension stays last, as the writers require.
inline std::string sharedTempPath(const std::string& name) {
  const std::filesystem::path n(name);
  const std::string p =
      (std::filesystem::temp_directory_path() /
       ("rangefuse-" + n.stem().string() + "-" + std::to_string(getpid()) + n.extension().string()))
          .string();
  return mpi::broadcastString(p, 0, MPI_COMM_WORLD);
}

}  // namespace rangefuse::test
