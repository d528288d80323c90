#include "CliCommon.h"

#include <fstream>
#include <iostream>

#include "rangefuse/parallel/Mpi.h"

namespace po = boost::program_options;

namespace rangefuse::cli {

bool parseOptions(int argc, char** argv, const po::options_description& desc, po::variables_map& vm,
                  const std::string& example) {
  po::store(po::command_line_parser(argc, argv).options(desc).run(), vm);
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
