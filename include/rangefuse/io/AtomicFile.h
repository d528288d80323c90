// Whole-file writes that never leave a partial file under the final name.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace rangefuse::io {

/// The name a file is written under before it is renamed to `path`: `path`.tmp.
std::string temporaryPath(const std::string& path);

/// Calls `write` on a stream to `path`.tmp, then renames it to `path`. On any error the
/// temporary is removed and InputError is thrown naming the file.
void writeAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// Renames a finished temporary file `tmp` to `path`; on failure removes it and throws
/// InputError naming `path` (for writers that make `tmp` through a C library).
void moveIntoPlace(const std::string& tmp, const std::string& path);

}  // namespace rangefuse::io
