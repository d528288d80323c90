#include <boost/program_options.hpp>

#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/fuse/FuseParameters.h"

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
  if (!p.implicitValue.empty()) value->implicit_value(p.implicitValue);
  value->notifier([&p, &o, text](const std::string& given) {
    if (p.required || given != text) parseParameter(p, o, given);
  });
  add(p.option.c_str(), value, p.help.c_str());
}

}  // namespace

void addFieldOptions(po::options_description& d, FuseOptions& o) {
  auto add = d.add_options();
  add("help,h", "show this help");
  add("config", po::value<std::string>(),
      "read options from an .ini file (key = value, same names)");
  for (const FuseParameter& p : fuseParameters())
    if (buildsField(p.group)) addParameter(add, p, o);
  addLimitOptions(d, o.limits);
}

void addLimitOptions(po::options_description& d, InputLimits& limits) {
  auto add = d.add_options();
  add("max-elements", po::value(&limits.maxElements)->default_value(limits.maxElements),
      "refuse a PLY element (vertices, faces, cells) or checkpoint metadata larger than this");
  add("max-grid-cells", po::value(&limits.maxGridCells)->default_value(limits.maxGridCells),
      "refuse a range grid with more num_cols x num_rows cells than this");
  add("max-voxels", po::value(&limits.maxVoxels)->default_value(limits.maxVoxels),
      "refuse a field that needs more voxels than this, all ranks together (~40 bytes each)");
}

void addSourceOptions(po::options_description& d, io::ScanSourceOptions& source) {
  // The help is fuse's own, so that every command describes these options alike.
  auto help = [](const std::string& option) {
    for (const FuseParameter& p : fuseParameters())
      if (p.option == option) return p.help;
    return std::string();
  };
  static const std::string format = help("scan-format"), intrinsics = help("intrinsics"),
                           depthMax = help("depth-max"), depthScale = help("depth-scale");
  auto add = d.add_options();
  add("scan-format", po::value(&source.format)->default_value(source.format), format.c_str());
  add("intrinsics", po::value(&source.intrinsics), intrinsics.c_str());
  add("depth-max", po::value(&source.maxDepth)->default_value(source.maxDepth), depthMax.c_str());
  add("depth-scale", po::value(&source.depthScale)->default_value(source.depthScale),
      depthScale.c_str());
}

po::options_description fuseOptions(FuseOptions& o) {
  po::options_description d("rangefuse fuse: fuse range scans into one mesh");
  d.add_options()("help,h", "show this help")(
      "config", po::value<std::string>(),
      "read options from an .ini file (key = value, same names)");
  // One section a group, in the table's group order.
  for (OptionGroup g :
       {OptionGroup::Input, OptionGroup::Field, OptionGroup::Output, OptionGroup::Registration,
        OptionGroup::Tracking, OptionGroup::Checkpoint, OptionGroup::Resources}) {
    po::options_description section(groupTitle(g));
    auto add = section.add_options();
    for (const FuseParameter& p : fuseParameters())
      if (p.group == g) addParameter(add, p, o);
    d.add(section);
  }
  po::options_description limits("Input limits");
  addLimitOptions(limits, o.limits);
  d.add(limits);
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
  return runFuse(o, comm);
}

}  // namespace rangefuse::cli
