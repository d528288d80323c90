// What this process has passed through MPI: counted at MPI's profiling interface (the calls
// rangefuse makes are wrapped and handed on to their PMPI_ names), so every message of the
// byte helpers, every collective and HDF5's own point-to-point traffic is counted.
#pragma once

#include <cstdint>

namespace rangefuse::mpi {

/// Payload bytes and calls since the process started: a point-to-point message counts its
/// bytes once, where it is sent and where it is received; a collective counts what the rank
/// hands in as sent and what it gets back as received (not the algorithm's own messages).
struct Traffic {
  uint64_t bytesSent = 0, bytesReceived = 0;
  uint64_t calls = 0;  ///< point-to-point messages and collective calls
};

/// This process's traffic so far.
Traffic traffic();

}  // namespace rangefuse::mpi
