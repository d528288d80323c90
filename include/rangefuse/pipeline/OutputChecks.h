// What a fuse run will write, checked before it reads a scan, and its size once bricks are known.
#pragma once

#include <string>
#include <vector>

#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse {

/// Throws InputError for the first output path that cannot be written; that two outputs share
/// (temporary names included); that is a file the run reads (the options file, the scan list
/// and every file it names, the checkpoint resumed unless it is the one updated) or lies in a
/// followed folder; or, for a checkpoint that exists and is not resumed, without --overwrite.
/// Every rank writes the mesh and the checkpoint (parallel I/O), so every rank checks those;
/// rank 0 alone the report, preview and poses.
void checkOutputs(const RunSettings& settings, int rank);

/// The files a run writes, each with the temporary name it is written under first.
std::vector<io::RolePath> outputFiles(const OutputSettings& outputs);

/// Warnings (empty when there is room) for the checkpoint and the mesh of a field of `layout`
/// whose folders have less free space than their estimated size: the checkpoint holds 24 bytes
/// a voxel; the mesh about 2 B^2 triangles a brick, B the brick size.
std::vector<std::string> storageWarnings(const OutputSettings& outputs, bool normals,
                                         const BrickLayout& layout);

}  // namespace rangefuse
