// The data lines of small text files (trajectories, frame lists), private to the readers.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace rangefuse::io::internal {

/// The lines of a text file with their numbers, '#' comments and blank lines skipped. Throws
/// InputError naming the file when it cannot be opened.
std::vector<std::pair<int, std::string>> dataLines(const std::string& path);

/// "PATH: line N", for messages.
std::string lineOf(const std::string& path, int line);

}  // namespace rangefuse::io::internal
