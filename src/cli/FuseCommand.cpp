#include <boost/program_options.hpp>

#include "CliCommon.h"
#include "Commands.h"
#include "InterruptHint.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/run/FuseJob.h"

namespace po = boost::program_options;

namespace rangefuse::cli {

namespace {

/// Adds the parameter as a text value converted by the table on notify (so bad values name
/// their option); defaults come from a default FuseOptions and are not re-parsed.
void addParameter(po::options_description_easy_init& add, const FuseParameter& p, FuseOptions& o) {
  static const FuseOptions defaults;
  auto* value = po::value<std::string>();
  const std::string text = parameterText(p, defaults);
  if (!p.required && !text.empty()) value->default_value(text);
  if (*p.implicitValue) value->implicit_value(p.implicitValue);
  value->notifier([&p, &o, text](const std::string& given) {
    if (p.required || given != text) parseParameter(p, o, given);
  });
  add(p.option.c_str(), value, p.help.c_str());
}

/// --help and --config, then one section for each of `groups` (in that order) holding the
/// table's options of that group, `own` (if any) after the input, and the input limits last.
void addSections(po::options_description& d, FuseOptions& o,
                 std::initializer_list<OptionGroup> groups,
                 const po::options_description* own = nullptr) {
  d.add_options()("help,h", "show this help")(
      "config", po::value<std::string>(),
      "read options from an .ini file (key = value, same names)");
  for (OptionGroup g : groups) {
    po::options_description section(groupTitle(g));
    auto add = section.add_options();
    for (const FuseParameter& p : fuseParameters())
      if (p.group == g) addParameter(add, p, o);
    d.add(section);
    if (g == OptionGroup::Input && own) d.add(*own);
  }
  po::options_description limits("Input limits");
  addLimitOptions(limits, o.limits, true);
  d.add(limits);
}

/// Fuse's help of an option, with `--scans` replaced by what the command reads.
std::string helpOf(const std::string& option, const std::string& reads) {
  for (const FuseParameter& p : fuseParameters())
    if (p.option == option) {
      std::string text = p.help;
      const size_t at = text.find("--scans");
      if (at != std::string::npos) text.replace(at, 7, reads);
      return text;
    }
  return {};
}

}  // namespace

void addFieldOptions(po::options_description& d, FuseOptions& o,
                     const po::options_description& own) {
  addSections(d, o, {OptionGroup::Input, OptionGroup::Field, OptionGroup::Resources}, &own);
}

void addLimitOptions(po::options_description& d, InputLimits& limits, bool fields) {
  auto add = d.add_options();
  add("max-elements", po::value(&limits.maxElements)->default_value(limits.maxElements),
      "refuse a PLY element (vertices, faces, cells) or checkpoint metadata larger than this");
  add("max-grid-cells", po::value(&limits.maxGridCells)->default_value(limits.maxGridCells),
      "refuse a range grid with more num_cols x num_rows cells than this");
  if (fields)
    add("max-voxels", po::value(&limits.maxVoxels)->default_value(limits.maxVoxels),
        "refuse a field that needs more voxels than this, all ranks together (~40 bytes each)");
}

void addSourceOptions(po::options_description& d, io::ScanSourceOptions& source,
                      const std::string& reads) {
  // The help is fuse's own, so that every command describes these options alike (Boost copies
  // the text).
  auto add = d.add_options();
  add("scan-format", po::value(&source.format)->default_value(source.format),
      helpOf("scan-format", reads).c_str());
  add("intrinsics", po::value(&source.intrinsics), helpOf("intrinsics", reads).c_str());
  add("depth-max", po::value(&source.depthMax)->default_value(source.depthMax),
      helpOf("depth-max", reads).c_str());
  add("depth-scale", po::value(&source.depthScale)->default_value(source.depthScale),
      helpOf("depth-scale", reads).c_str());
}

po::options_description fuseOptions(FuseOptions& o) {
  po::options_description d("rangefuse fuse: fuse range scans into one mesh");
  addSections(
      d, o,
      {OptionGroup::Input, OptionGroup::Field, OptionGroup::Output, OptionGroup::Registration,
       OptionGroup::Tracking, OptionGroup::Checkpoint, OptionGroup::Resources});
  return d;
}

int fuseCommand(int argc, char** argv, MPI_Comm comm) {
  FuseOptions o;
  po::variables_map vm;
  const int parsed = parseCollectively(
      argc, argv, fuseOptions(o), vm,
      "mpirun -np 2 rangefuse fuse --scans bun.conf --voxel 0.001 --out bunny.ply", "fuse", comm);
  if (parsed >= 0) return parsed;
  for (const auto& [name, value] : vm)
    if (!value.defaulted()) o.givenOptions.push_back(name);
  if (vm.count("config")) o.outputs.config = vm["config"].as<std::string>();
  setInterruptHint(fuseInterruptHint(
      o.outputs.checkpoint, !o.outputs.resume.empty() && o.outputs.resume == o.outputs.checkpoint));
  return runFuse(o, comm);
}

}  // namespace rangefuse::cli
