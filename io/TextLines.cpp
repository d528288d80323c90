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

std::vector<std::vector<double>> squareRows(const std::string& path, size_t n,
                                            const std::string& what) {
  const auto lines = dataLines(path);
  const std::string rows = std::to_string(n) + " rows of " + std::to_string(n) + " numbers";
  if (lines.size() != n)
    throw InputError(path + ": expected " + what + " (" + rows + "), found " +
                     std::to_string(lines.size()) + " lines");
  const std::string row = "a matrix row of " + std::to_string(n) + " numbers";
  std::vector<std::vector<double>> out;
  for (const auto& [number, text] : lines)
    out.push_back(numbers(text, n, lineOf(path, number), row.c_str()));
  return out;
}

}  // namespace rangefuse::io::internal
