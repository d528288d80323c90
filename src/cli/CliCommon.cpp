#include "CliCommon.h"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "rangefuse/parallel/Mpi.h"

namespace po = boost::program_options;

namespace rangefuse::cli {

namespace {

/// Edits (insertions, deletions, substitutions) that turn `a` into `b`.
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The words of a hyphenated option name, sorted: "max-depth" and "depth-max" share them.
std::vector<std::string> wordsOf(const std::string& name) {
  std::vector<std::string> words;
  std::stringstream in(name);
  for (std::string w; std::getline(in, w, '-');) words.push_back(w);
  std::sort(words.begin(), words.end());
  return words;
}

}  // namespace

std::string suggestOption(const std::string& given, const po::options_description& desc) {
  std::string name = given;
  while (!name.empty() && name[0] == '-') name.erase(0, 1);
  name = name.substr(0, name.find('='));
  std::string best;
  size_t bestDistance = 3;  // two edits at most: "color" -> "colour"
  for (const auto& option : desc.options()) {
    const std::string& known = option->long_name();
    const size_t d = wordsOf(known) == wordsOf(name) ? 0 : editDistance(name, known);
    if (d < bestDistance) best = known, bestDistance = d;
  }
  return best.empty() ? "" : "did you mean --" + best + "?";
}

std::string unknownOptionMessage(const po::unknown_option& e, const po::options_description& desc) {
  const std::string hint = suggestOption(e.get_option_name(), desc);
  return std::string(e.what()) + (hint.empty() ? "" : "; " + hint);
}

bool parseOptions(int argc, char** argv, const po::options_description& desc, po::variables_map& vm,
                  const std::string& example) {
  try {
    po::store(po::command_line_parser(argc, argv).options(desc).run(), vm);
  } catch (const po::unknown_option& e) {
    throw po::error(unknownOptionMessage(e, desc));
  }
  if (vm.count("help")) {
    if (mpi::rank() == 0)
      std::cout << desc << (example.empty() ? "" : "\nExample:\n  " + example + "\n");
    return false;
  }
  if (vm.count("config")) {
    const std::string path = vm["config"].as<std::string>();
    std::ifstream in(path);
    if (!in) throw po::error(path + ": cannot open config file");
    try {
      po::store(po::parse_config_file(in, desc), vm);
    } catch (const po::error& e) {
      // A scan list or another file given to --config is the usual cause: say which file.
      throw po::error(path + ": " + e.what() +
                      " (--config takes an .ini of options, 'key = value' a line; a scan list "
                      "goes to --scans)");
    }
  }
  po::notify(vm);
  return true;
}

int parseCollectively(int argc, char** argv, const po::options_description& desc,
                      po::variables_map& vm, const std::string& example, const std::string& command,
                      MPI_Comm comm) {
  std::string error;
  bool run = false;
  try {
    run = parseOptions(argc, argv, desc, vm, example);
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!mpi::agree(error.empty(), error + " (see 'rangefuse " + command + " --help')", comm))
    return 2;
  return run ? -1 : 0;
}

int runOnRoot(MPI_Comm comm, const std::function<int()>& fn) {
  int code = 0;
  std::string error;
  if (mpi::rank(comm) == 0) {
    try {
      code = fn();
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (!mpi::agree(error.empty(), error, comm)) return 1;
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  return code;
}

}  // namespace rangefuse::cli
