#include "TextLines.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

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

std::vector<double> numbers(const std::string& text, size_t count, const std::string& where,
                            const char* expected) {
  std::istringstream in(text);
  std::vector<double> v;
  std::string word;
  while (in >> word) {
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    if (*end != '\0' || v.size() == count)
      throw InputError(where + ": expected " + expected + ", found '" + word + "'");
    if (!std::isfinite(x)) throw InputError(where + ": NaN or Inf in " + expected);
    v.push_back(x);
  }
  if (v.size() != count) throw InputError(where + ": expected " + expected);
  return v;
}

std::string lineOf(const std::string& path, int line) {
  return path + ": line " + std::to_string(line);
}

}  // namespace rangefuse::io::internal
