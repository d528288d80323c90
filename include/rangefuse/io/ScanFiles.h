// The scans a job reads, whatever files hold them: a Stanford .conf naming range-grid PLY files
// (or scans of PTX files, as FILE.ptx#K), or a Leica PTX file itself.
#pragma once

#include <string>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/io/Conf.h"

namespace rangefuse::io {

/// The scans `path` lists: a .ptx file gives all its scans, named FILE.ptx#1, #2, ..., posed by
/// their transforms; anything else is read as a .conf, whose FILE.ptx#K names are looked up in
/// their files. Throws InputError naming the file at fault.
ConfFile readScanList(const std::string& path, const InputLimits& limits = {});

/// The grid of one listed scan, in its own frame.
RangeGrid readScanGrid(const ConfScan& scan, const InputLimits& limits = {});

}  // namespace rangefuse::io
