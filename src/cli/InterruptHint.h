// What a run says when Ctrl-C (SIGINT) or a scheduler's SIGTERM ends it: how to go on.
#pragma once

#include <string>

namespace rangefuse::cli {

/// Installs handlers for SIGINT and SIGTERM that print the hint last set (on this rank only
/// when `printing`) and then end the process as the signal would have.
void installInterruptHint(bool printing);

/// The line printed when the run is interrupted (empty: none).
void setInterruptHint(const std::string& hint);

/// The hint of a fuse run writing `checkpoint` (empty: none), which `resumesIt` already.
std::string fuseInterruptHint(const std::string& checkpoint, bool resumesIt);

}  // namespace rangefuse::cli
