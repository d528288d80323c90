#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallelio/Checkpoint.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/render/Render.h"

namespace po = boost::program_options;

namespace rangefuse::cli {
namespace {

struct RenderOptions {
  FuseOptions field;
  std::string out, view, slice, checkpoint, up = "auto";
  int width = 512, height = 512;
};

/// What to draw, parsed and checked before any work is done.
struct Picture {
  bool slice = false;
  int axis = 0;
  double value = 0;
  ViewSettings view;
};

Picture parsePicture(const RenderOptions& o) {
  if (!o.checkpoint.empty() && !o.field.scans.empty())
    throw InputError("render: give --checkpoint or --scans, not both");
  if (o.out.empty()) throw InputError("render: --out FILE.png is required");
  io::FileRoles files;
  files.outputs = io::outputWithTemporary("picture", o.out);
  files.inputs = {{"checkpoint", o.checkpoint}, {"options file", o.field.outputs.config}};
  if (!o.field.scans.empty())
    for (std::string& f : io::scanListFiles(o.field.scans))
      files.inputs.push_back({"scan list's file", std::move(f)});
  io::refuseOverlaps(files);
  io::requireExtension(o.out, "picture", {".png"});
  if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
    throw InputError("render: --width and --height must be between 1 and 16384");
  Picture p;
  p.slice = !o.slice.empty();
  if (p.slice) parseSlice(o.slice, p.axis, p.value);
  p.view.width = o.width;
  p.view.height = o.height;
  if (!o.view.empty()) parseView(o.view, p.view);
  p.view.up = upAxis(o.up, false);  // auto: settled by the scans once they are known
  return p;
}

int run(const RenderOptions& o, MPI_Comm comm) {
  std::string error;
  Picture pic;
  try {
    pic = parsePicture(o);
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!mpi::agree(error.empty(), error, comm)) return 2;
  FusedField field;
  float minWeight = o.field.minWeight;
  if (!o.checkpoint.empty()) {
    // The field as a checkpoint holds it, re-partitioned over these ranks.
    if (!mpi::collectively(comm, [&] {
          const io::CheckpointMeta meta =
              io::readCheckpointMeta(o.checkpoint, comm, o.field.limits);
          field.store = io::readCheckpointField(o.checkpoint, meta, field.layout, comm);
          minWeight = meta.parameters.value("min_weight", 0.0f);
          pic.view.up =
              upAxis(o.up, !meta.scanNames.empty() &&
                               io::sensorKindOf(meta.scanNames[0]) == io::SensorKind::station);
        }))
      return 1;
  } else {
    Progress progress(comm);
    RankCounters counters;
    if (!mpi::collectively(comm, [&] {
          validateFuseOptions(o.field);
          pic.view.up = upAxis(o.up, io::sensorKindOf(o.field.scans) == io::SensorKind::station);
        }))
      return 1;
    const RunSettings s = runSettings(o.field);
    if (!buildField(s.read, s.field, comm, progress, field, counters)) return 1;
  }
  Image img;
  if (pic.slice) {
    // Only the bricks the plane cuts travel to rank 0.
    const int plane = slicePlane(field.store->grid(), pic.axis, pic.value);
    const int B = field.store->grid().brick;
    const auto cut = [&](const BrickCoord& b) { return floorDiv(plane, B) == b[pic.axis]; };
    img = renderSlice(SparseField::gather(*field.store, minWeight, 0, comm, cut), pic.axis,
                      pic.value);
  } else {
    img = renderDistributed(*field.store, minWeight, pic.view, 0, comm);
  }
  return runOnRoot(comm, [&] {
    io::writePng(o.out, img);
    std::printf("render: %dx%d picture -> %s\n", img.width, img.height, o.out.c_str());
    return 0;
  });
}

}  // namespace

int renderCommand(int argc, char** argv, MPI_Comm comm) {
  RenderOptions o;
  po::options_description d("rangefuse render: a PNG of the fused field (surface or slice)");
  po::options_description picture("Picture");
  picture.add_options()("out", po::value(&o.out), "PNG to write")(
      "view", po::value(&o.view), "AZIMUTH,ELEVATION in degrees (azimuth about the --up axis)")(
      "up", po::value(&o.up)->default_value(o.up),
      "the world's up axis: y (0 azimuth = from +z), z (0 = from -y) or auto (z for scanner "
      "stations, PTX and E57, else y)")("slice", po::value(&o.slice),
                                        "AXIS=VALUE: a slice of the distance field instead")(
      "width", po::value(&o.width)->default_value(512), "picture width, pixels")(
      "height", po::value(&o.height)->default_value(512), "picture height, pixels")(
      "checkpoint", po::value(&o.checkpoint), "render the field of an HDF5 checkpoint instead");
  addFieldOptions(d, o.field, picture);
  po::variables_map vm;
  const int parsed = parseCollectively(
      argc, argv, d, vm,
      "mpirun -np 2 rangefuse render --scans bun.conf --voxel 0.001 --view 30,20 --out bunny.png",
      "render", comm);
  if (parsed >= 0) return parsed;
  if (vm.count("config")) o.field.outputs.config = vm["config"].as<std::string>();
  return run(o, comm);
}

}  // namespace rangefuse::cli
