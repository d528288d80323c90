// One entry per reader of outside input, shared by the libFuzzer targets and the
// regression tests that replay every input the fuzzers ever crashed on.
#pragma once

#include <cstdint>
#include <string>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Limits.h"

namespace rangefuse::fuzz {

/// Each entry feeds `bytes` to one reader. A clean refusal (InputError) returns normally;
/// anything else (another exception, a crash, a sanitizer report) is a bug.
void rangeGridPly(const std::string& bytes);
void meshPly(const std::string& bytes);
void conf(const std::string& bytes);
void fuseIni(const std::string& bytes);

/// Sensor files, written to a scratch folder first (their readers take paths): a PTX file, a
/// 16-bit PNG, and a depth-image folder whose first byte picks TUM (even) or Redwood (odd) and
/// whose other bytes, cut at NULs, are its text files (TUM: depth.txt, groundtruth.txt,
/// camera_intrinsic.json; Redwood: trajectory.log, camera_intrinsic.json) beside two valid
/// frames. A colour image: the first byte picks JPEG (even) or PNG (odd), the rest is the file.
void ptx(const std::string& bytes);
/// An E57 file: the first byte picks the rest as the file's bytes (odd: pages and checksums as
/// given, reaching the checksum checks) or as its logical bytes (even: laid on pages with their
/// checksums, so that mutations reach the header, the XML and the packets).
void e57(const std::string& bytes);
void depthPng(const std::string& bytes);
void depthSequence(const std::string& bytes);
void colourImage(const std::string& bytes);

/// Builds a structurally valid HDF5 file whose attributes, dataset shapes, types, counts
/// and metadata are chosen by `bytes`, then loads it as a checkpoint. Needs MPI initialised.
void checkpoint(const std::string& bytes);

/// Runs fn; a clean refusal (InputError) is swallowed, anything else escapes.
template <class Fn>
void refusedCleanly(Fn&& fn) {
  try {
    fn();
  } catch (const InputError&) {
  }
}

/// Limits small enough that libFuzzer's 2 GiB malloc limit is never what stops a run.
InputLimits fuzzLimits();

/// Names of the entries above, and the entry called `name` (nullptr if unknown).
using Entry = void (*)(const std::string&);
Entry entryNamed(const std::string& name);

}  // namespace rangefuse::fuzz
