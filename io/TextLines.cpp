#include "TextLines.h"

#include <fstream>

#include "rangefuse/core/Error.h"

namespace rangefuse::io::internal {

std::vector<std::pair<int, std::string>> dataLines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  std::vector<std::pair<int, std::string>> lines;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    lines.emplace_back(n, line);
  }
  return lines;
}

std::string lineOf(const std::string& path, int line) {
  return path + ": line " + std::to_string(line);
}

}  // namespace rangefuse::io::internal
