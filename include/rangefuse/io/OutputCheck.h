// Checks of output paths made before any work, so that a mistyped path costs a second, not a run.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rangefuse::io {

/// Throws InputError naming `path` and the `what` (e.g. "mesh") when it cannot be written:
/// its folder is missing, not a folder or not writable, or the path is a folder or a file
/// that is not writable. Creates nothing.
void checkWritable(const std::string& path, const std::string& what);

/// Throws InputError naming `path`, the `what` and the extensions its writer produces when
/// `path` ends in none of `extensions` (".ply", compared without case): a writer never puts one
/// format under another's name.
void requireExtension(const std::string& path, const std::string& what,
                      const std::vector<std::string>& extensions);

/// Bytes free for an unprivileged user in the folder that would hold `path`; -1 when unknown.
int64_t freeBytes(const std::string& path);

/// A warning line (empty when there is room or the free space is unknown) when the folder of
/// `path` has less than `bytes` free for the `what`.
std::string spaceWarning(const std::string& path, uint64_t bytes, const std::string& what);

}  // namespace rangefuse::io
