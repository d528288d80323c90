// Whether a file a command is about to write is one it reads, or one it writes twice: checked
// before any work so that no run ever overwrites a user's scans, scan list or checkpoint.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace rangefuse::io {

/// Where a path puts a file on the file system: an existing file by its device and inode (so
/// symbolic links, hard links, "./" and ".." all name it alike), a file not yet written by its
/// folder's device and inode and its own name.
struct FilePlace {
  dev_t device = 0;
  ino_t inode = 0;
  std::string name;  ///< empty for an existing file; the new file's name in its folder
  bool operator==(const FilePlace& o) const {
    return device == o.device && inode == o.inode && name == o.name;
  }
};

/// The place `path` names; nothing when neither it nor its folder exists.
std::optional<FilePlace> placeOf(const std::string& path);

/// True when `a` and `b` name one file (existing or to be written).
bool sameFile(const std::string& a, const std::string& b);

/// True when `path` (existing or to be written) lies somewhere inside folder `folder`.
bool inside(const std::string& path, const std::string& folder);

/// A file a command reads or writes and what it is to the command ("mesh", "scan list").
struct RolePath {
  std::string role;
  std::string path;
};

/// What a command is about to write and what it reads.
struct FileRoles {
  std::vector<RolePath> outputs;  ///< files it writes, temporaries included
  std::vector<RolePath> inputs;   ///< files it reads
  /// Folders it reads new files from while it runs (--follow): nothing may be written there.
  std::vector<RolePath> watched;
};

/// Throws InputError naming both files and their roles when an output is an input, is another
/// output, or lies inside a watched folder. Empty paths are skipped.
void refuseOverlaps(const FileRoles& files);

/// Every regular file under `folder` (recursively, links followed), for a folder whose files
/// a command reads (a depth-image sequence).
std::vector<std::string> filesUnder(const std::string& folder);

/// `path` plus the temporary name it is written under first (AtomicFile.h), as outputs of
/// role `role`.
std::vector<RolePath> outputWithTemporary(const std::string& role, const std::string& path);

}  // namespace rangefuse::io
