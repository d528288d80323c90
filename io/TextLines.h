// The data lines of small text files (trajectories, frame lists), private to the readers.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace rangefuse::io::internal {

/// The lines of a text file with their numbers, '#' comments and blank lines skipped. Throws
/// InputError naming the file when it cannot be opened.
std::vector<std::pair<int, std::string>> dataLines(const std::string& path);

/// Reads `count` finite numbers from a line, refusing fewer, more or non-finite ones (strtod,
/// unlike stream extraction, reads "nan" and "inf", so they are named as such); `where` and
/// `expected` make the message ("FILE: line 3: expected a matrix row of 4 numbers").
std::vector<double> numbers(const std::string& text, size_t count, const std::string& where,
                            const char* expected);

/// The n rows of n numbers a small matrix file holds (comments and blank lines skipped).
/// Throws InputError naming the file (and the line) otherwise; `what` says what it should
/// hold ("a 3 x 3 camera matrix K").
std::vector<std::vector<double>> squareRows(const std::string& path, size_t n,
                                            const std::string& what);

/// "PATH: line N", for messages.
std::string lineOf(const std::string& path, int line);

}  // namespace rangefuse::io::internal
