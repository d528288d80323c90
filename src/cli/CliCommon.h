// Shared plumbing of the subcommands: option parsing and running on rank 0.
#pragma once

#include <mpi.h>

#include <boost/program_options.hpp>
#include <functional>
#include <string>

#include "rangefuse/options/FuseParameters.h"

namespace rangefuse::cli {

/// Parses the command line, then `--config FILE` if the description has it (the command
/// line wins). Prints the help on rank 0 and returns false for --help. Throws on bad options.
bool parseOptions(int argc, char** argv, const boost::program_options::options_description& desc,
                  boost::program_options::variables_map& vm, const std::string& example);

/// "did you mean --colour?" for an option `given` that `desc` does not have, naming the option
/// of the same words in another order or within two edits of it; empty when none is.
std::string suggestOption(const std::string& given,
                          const boost::program_options::options_description& desc);

/// The parser's message for an unknown option, with suggestOption's hint when there is one.
std::string unknownOptionMessage(const boost::program_options::unknown_option& e,
                                 const boost::program_options::options_description& desc);

/// Parses collectively: every rank returns 2 on a bad option (message printed once), 0
/// after --help, -1 when the command should run.
int parseCollectively(int argc, char** argv,
                      const boost::program_options::options_description& desc,
                      boost::program_options::variables_map& vm, const std::string& example,
                      const std::string& command, MPI_Comm comm);

/// Adds --help/--config, the options that define the fused field (scans, voxel, envelope, ...)
/// in fuse's sections, and the command's `own` section after the input: for render.
void addFieldOptions(boost::program_options::options_description& desc, FuseOptions& options,
                     const boost::program_options::options_description& own);

/// Every option of `rangefuse fuse`, bound to `options`.
boost::program_options::options_description fuseOptions(FuseOptions& options);

/// Adds --max-elements, --max-grid-cells and, for commands that build a field, --max-voxels
/// (memory bounds on input).
void addLimitOptions(boost::program_options::options_description& desc, InputLimits& limits,
                     bool fields);

/// --scan-format, --intrinsics, --depth-max and --depth-scale, for commands that read scan lists
/// (fuse has them in its option table); their help says they apply to `reads` (e.g. "--seen").
void addSourceOptions(boost::program_options::options_description& desc,
                      io::ScanSourceOptions& source, const std::string& reads);

/// Runs fn on rank 0 only; every rank returns its exit code, or 1 if it threw (the error
/// printed once).
int runOnRoot(MPI_Comm comm, const std::function<int()>& fn);

}  // namespace rangefuse::cli
