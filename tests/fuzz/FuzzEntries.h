// One entry per reader of outside input, shared by the libFuzzer targets and the
// regression tests that replay every input the fuzzers ever crashed on.
#pragma once

#include <cstdint>
#include <string>

#include "rangefuse/core/Limits.h"

namespace rangefuse::fuzz {

/// Each entry feeds `bytes` to one reader. A clean refusal (InputError) returns normally;
/// anything else (another exception, a crash, a sanitizer report) is a bug.
void rangeGridPly(const std::string& bytes);
void meshPly(const std::string& bytes);
void conf(const std::string& bytes);
void fuseIni(const std::string& bytes);

/// Builds a structurally valid HDF5 file whose attributes, dataset shapes, types, counts
/// and metadata are chosen by `bytes`, then loads it as a checkpoint. Needs MPI initialised.
void checkpoint(const std::string& bytes);

/// Limits small enough that libFuzzer's 2 GiB malloc limit is never what stops a run.
InputLimits fuzzLimits();

/// Names of the entries above, and the entry called `name` (nullptr if unknown).
using Entry = void (*)(const std::string&);
Entry entryNamed(const std::string& name);

}  // namespace rangefuse::fuzz
