#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/DepthSequence.h"
#include "rangefuse/io/E57.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/io/Ptx.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/scan/PaintedTruth.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

namespace po = boost::program_options;
using nlohmann::json;

namespace rangefuse::cli {
namespace {

struct ScanOptions {
  std::string mesh, shape, out, path = "sphere", format = "ply", sensor = "none", sensorWithout;
  std::string e57Coordinates = "double";  ///< double, single, scaled (0.1 mm steps), spherical
  bool e57Loose = false;                  ///< E57 without row and column indices
  double scale = 1;
  bool ascii = false, bigEndian = false, jpeg = false;
  ScanSettings settings;
  InputLimits limits;
};

json vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

json groundTruth(const ScanOptions& o, const SyntheticSet& set) {
  const ScanSettings& s = o.settings;
  json j = {{"source", o.mesh.empty() ? "shape:" + o.shape : o.mesh},
            {"settings",
             {{"views", s.views},
              {"width", s.width},
              {"height", s.height},
              {"voxel", s.voxel},
              {"fov_deg", s.fovDeg},
              {"noise_voxels", s.noise},
              {"depth_noise", s.depthNoise},
              {"disparity_baseline", s.disparityBaseline},
              {"sensor", o.sensor},
              {"sensor_without", o.sensorWithout},
              {"path", o.path},
              {"format", o.format},
              {"scale", o.scale},
              {"outliers", s.outliers},
              {"patches", s.patches},
              {"rot_deg", s.rotDeg},
              {"trans_voxels", s.transVox},
              {"seed", s.seed},
              {"texture", s.texture},
              {"colour_shift", s.colourShift}}},
            {"object_centre", vec(set.centre)},
            {"object_radius", set.radius}};
  for (const auto& sc : set.scans) {
    json scan = {{"name", sc.name},
                 {"viewpoint", vec(sc.viewpoint)},
                 {"points", sc.grid.points.size()},
                 {"sensor", sc.grid.spherical ? "station" : "pinhole"},
                 {"truth", io::poseToJson(sc.truth)},
                 {"perturbed", io::poseToJson(sc.perturbed)},
                 {"perturbation",
                  {{"rotation_deg", vec(sc.rotationDeg)}, {"translation", vec(sc.translation)}}}};
    if (sc.grid.pinhole) {
      const Pinhole& p = *sc.grid.pinhole;
      scan.update({{"fx", p.fx}, {"fy", p.fy}, {"cx", p.cx}, {"cy", p.cy}});
    }
    j["scans"].push_back(scan);
  }
  j["patches"] = json::array();
  for (const auto& p : set.patches) {
    json corners = json::array();
    for (const auto& c : p.corners) corners.push_back(vec(c));
    j["patches"].push_back({{"scan", p.scan}, {"corners", corners}});
  }
  return j;
}

bool isSequenceFormat(const std::string& format) {
  return format == "tum" || format == "redwood" || format == "7scenes";
}

/// A depth sequence's unit, as its layout has it: TUM's 1/5000 m, the others' millimetre.
double depthUnit(const std::string& format) {
  return format == "tum" ? 1.0 / 5000 : 1e-3;
}

/// Throws InputError when the scans' depths do not fit 16-bit PNG counts of `unit` world units:
/// the farthest past 65535 counts, or a voxel under four counts (the depth steps would show),
/// with the --scale that would fit.
void checkDepthsFit(const ScanOptions& o, const SyntheticSet& set, double unit) {
  double farthest = 0;
  for (const auto& s : set.scans)
    for (const Eigen::Vector3d& p : s.grid.points) farthest = std::max(farthest, -p.z());
  const std::string format = "scan --format " + o.format + ": ";
  if (farthest / unit > 65535) {
    const double fit = std::pow(10, -std::ceil(std::log10(farthest / (0.9 * 65535 * unit))));
    std::ostringstream m;
    m << format << "depths reach " << farthest << " units, but its 16-bit PNGs hold "
      << 65535 * unit << " (" << 1 / unit
      << " counts a unit, the format's metres): scale the scene (--scale " << o.scale * fit
      << ") and the voxel with it (--voxel " << o.settings.voxel * fit << ")";
    throw InputError(m.str());
  }
  if (o.settings.voxel < 4 * unit) {
    std::ostringstream m;
    m << format << "--voxel " << o.settings.voxel << " is under four of its depth steps (" << unit
      << " units): scale the scene up and the voxel with it";
    throw InputError(m.str());
  }
}

/// Writes the scans as a TUM, Redwood or 7-Scenes depth sequence in `dir`, and perturbed.conf
/// beside it (its names are the frames' images, so it reads back as a scan list).
void writeSequence(const ScanOptions& o, const SyntheticSet& set, const std::string& dir) {
  const double unit = depthUnit(o.format);
  std::vector<io::DepthFrame> frames;
  for (const auto& s : set.scans)
    frames.push_back({io::depthImage(s.grid, unit), io::cameraPose(s.truth),
                      s.grid.colours.empty() ? Image{} : io::colourImage(s.grid)});
  const io::DepthCamera camera = io::depthCamera(set.scans.front().grid, unit);
  io::ConfFile listed;
  if (o.format == "tum") {
    io::writeTumSequence(dir, frames, camera, 1000.0, 30.0, o.jpeg);
    listed = io::readTumSequence(dir, {});
  } else if (o.format == "redwood") {
    io::writeRedwoodSequence(dir, frames, camera, o.jpeg);
    listed = io::readRedwoodSequence(dir, {});
  } else {
    io::writeSevenScenesSequence(dir, frames, camera);
    listed = io::readSevenScenesSequence(dir, {});
  }
  std::vector<io::ConfScan> perturbed = listed.scans;
  for (size_t k = 0; k < perturbed.size(); ++k) perturbed[k].pose = set.scans[k].perturbed;
  io::writeConf(dir + "/perturbed.conf", perturbed);
}

/// Writes the scans as range-grid PLY files with truth.conf and perturbed.conf.
void writeRangeGrids(const ScanOptions& o, const SyntheticSet& set, const std::string& dir) {
  std::vector<io::ConfScan> truth, perturbed;
  for (const auto& s : set.scans) {
    const std::string path = (std::filesystem::path(dir) / s.name).string();
    io::writeRangeGridPly(path, s.grid,
                          o.ascii       ? io::PlyEncoding::Ascii
                          : o.bigEndian ? io::PlyEncoding::BinaryBigEndian
                                        : io::PlyEncoding::BinaryLittleEndian);
    truth.push_back({s.name, path, s.truth});
    perturbed.push_back({s.name, path, s.perturbed});
  }
  io::writeConf(dir + "/truth.conf", truth);
  io::writeConf(dir + "/perturbed.conf", perturbed);
}

/// Writes the scans as one Leica PTX file, stations.ptx, or one E57 file, stations.e57, with
/// truth.conf and perturbed.conf naming its scans (stations.ptx#K, stations.e57#K).
void writeStations(const SyntheticSet& set, const std::string& dir, const std::string& format,
                   const io::E57Writing& e57) {
  std::vector<RangeGrid> grids;
  std::vector<Pose> poses;
  std::vector<io::ConfScan> truth, perturbed;
  for (size_t k = 0; k < set.scans.size(); ++k) {
    grids.push_back(set.scans[k].grid);
    poses.push_back(set.scans[k].truth);
    const std::string name = "stations." + format + "#" + std::to_string(k + 1);
    truth.push_back({name, "", set.scans[k].truth});
    perturbed.push_back({name, "", set.scans[k].perturbed});
  }
  if (format == "ptx")
    io::writePtx(dir + "/stations.ptx", grids, poses);
  else
    io::writeE57(dir + "/stations.e57", grids, poses, e57);
  io::writeConf(dir + "/truth.conf", truth);
  io::writeConf(dir + "/perturbed.conf", perturbed);
}

/// How `--format e57` stores its stations.
io::E57Writing e57Writing(const ScanOptions& o) {
  io::E57Writing how;
  const std::map<std::string, io::E57Coordinates> kinds = {
      {"double", io::E57Coordinates::cartesianDouble},
      {"single", io::E57Coordinates::cartesianSingle},
      {"scaled", io::E57Coordinates::cartesianScaled},
      {"spherical", io::E57Coordinates::sphericalDouble}};
  how.coordinates = kinds.at(o.e57Coordinates);
  how.structured = !o.e57Loose;
  return how;
}

ScanOptions checked(ScanOptions o) {
  const std::map<std::string, ViewPath> paths = {
      {"sphere", ViewPath::Sphere},     {"orbit", ViewPath::Orbit},
      {"stations", ViewPath::Stations}, {"handheld", ViewPath::Handheld},
      {"walk", ViewPath::Walk},         {"fastturns", ViewPath::FastTurns}};
  if (!paths.count(o.path))
    throw InputError("scan: --path must be sphere, orbit, stations, handheld, fastturns or walk");
  o.settings.path = paths.at(o.path);
  o.settings.sensor = DepthSensorModel::preset(o.sensor).without(o.sensorWithout);
  if (o.format != "ply" && !isSequenceFormat(o.format) && o.format != "ptx" && o.format != "e57")
    throw InputError("scan: --format must be ply, tum, redwood, 7scenes, ptx or e57");
  if (o.settings.texture < 0) throw InputError("scan: --texture must not be negative");
  if (o.settings.colourShift != 0 && !(o.settings.texture > 0))
    throw InputError("scan: --colour-shift needs --texture (a colour image to shift)");
  if (o.e57Coordinates != "double" && o.e57Coordinates != "single" &&
      o.e57Coordinates != "scaled" && o.e57Coordinates != "spherical")
    throw InputError("scan: --e57-coordinates must be double, single, scaled or spherical");
  if ((o.path == "stations") != (o.format == "ptx" || o.format == "e57"))
    throw InputError(
        "scan: stations (--path stations) are written as --format ptx or e57, and "
        "those formats hold stations only");
  if (!(o.scale > 0 && std::isfinite(o.scale)))
    throw InputError("scan: --scale must be positive and finite");
  return o;
}

int run(const ScanOptions& given) {
  const ScanOptions o = checked(given);
  if (o.mesh.empty() == o.shape.empty())
    throw InputError("scan: give exactly one of --mesh and --shape");
  if (o.out.empty()) throw InputError("scan: --out DIR is required");
  if (!o.mesh.empty() && io::inside(o.mesh, o.out))
    throw InputError(o.mesh + ": the mesh scanned lies inside --out " + o.out +
                     ", where scan writes its files (truth.ply among them); give another --out");
  checkLimit("scan",
             "--width x --height =", static_cast<double>(o.settings.width) * o.settings.height,
             o.limits.maxGridCells, "max-grid-cells");
  TriangleMesh mesh = o.mesh.empty() ? makeShape(o.shape) : io::readMeshPly(o.mesh, o.limits);
  for (Eigen::Vector3d& v : mesh.vertices) v *= o.scale;
  const SyntheticSet set = scanMesh(mesh, o.settings);
  if (isSequenceFormat(o.format)) checkDepthsFit(o, set, depthUnit(o.format));
  std::filesystem::create_directories(o.out);
  const auto file = [&](const std::string& name) {
    return (std::filesystem::path(o.out) / name).string();
  };
  size_t points = 0;
  for (const auto& s : set.scans) points += s.grid.points.size();
  if (o.format == "ply")
    writeRangeGrids(o, set, o.out);
  else if (o.format == "ptx" || o.format == "e57")
    writeStations(set, o.out, o.format, e57Writing(o));
  else
    writeSequence(o, set, o.out);
  // A quarter voxel: sharper than any fused mesh can be, so the truth does not blur the edges
  // that eval measures.
  if (o.settings.texture > 0) mesh = paintedTruth(mesh, o.settings.texture, o.settings.voxel / 4);
  io::writeMeshPly(file("truth.ply"), mesh);
  io::writeMeshPly(file("patches.ply"), patchMesh(set.patches));
  for (size_t k = 0; k < set.patches.size(); ++k)
    io::writeMeshPly(file("patch_" + std::to_string(k) + ".ply"), patchMesh({set.patches[k]}));
  io::writeJson(file("scan.json"), groundTruth(o, set));
  std::printf("scan: %zu views of %zu triangles, %zu points, %zu patches -> %s\n", set.scans.size(),
              mesh.faces.size(), points, set.patches.size(), o.out.c_str());
  return 0;
}

}  // namespace

int scanCommand(int argc, char** argv, MPI_Comm comm) {
  ScanOptions o;
  ScanSettings& s = o.settings;
  po::options_description d("rangefuse scan: synthetic range scans of a mesh, with ground truth");
  d.add_options()("help,h", "show this help")("config", po::value<std::string>(),
                                              "read options from an .ini file")(
      "mesh", po::value(&o.mesh), "mesh to scan (PLY)")(
      "shape", po::value(&o.shape),
      "built-in shape instead: sphere, torus, composite, room (8 m, inside) or desk (1.2 m)")(
      "views", po::value(&s.views)->default_value(24), "number of scans")(
      "width", po::value(&s.width)->default_value(320), "pixels per row")(
      "height", po::value(&s.height)->default_value(240), "rows")(
      "voxel", po::value(&s.voxel)->required(), "voxel size: the unit of --noise and --trans-vox")(
      "fov", po::value(&s.fovDeg)->default_value(0.0), "field of view, degrees (0: fitted)")(
      "noise", po::value(&s.noise)->default_value(0.0), "range noise sigma along the ray, voxels")(
      "depth-noise", po::bool_switch(&s.depthNoise),
      "noise grows with the square of the range (depth cameras); --noise holds at the path's "
      "distance")("sensor", po::value(&o.sensor)->default_value(o.sensor),
                  "a depth camera's faults: kinect (a Kinect v1 as 7-Scenes recorded it: depth "
                  "from 1/8-pixel disparity steps with noise, projector shadows, holes at edges, "
                  "grazing angles and dark spots, mixed returns, 0.8-3.5 m, a rolling shutter "
                  "and depth 10 ms late; scene in metres) or none")(
      "sensor-without", po::value(&o.sensorWithout),
      ("the --sensor without these faults (comma-separated): " + faultNames()).c_str())(
      "disparity-baseline", po::value(&s.disparityBaseline)->default_value(0.0),
      "depth from disparity in 1/8-pixel steps, as a structured-light camera (a "
      "Kinect: 0.075 m) with this baseline measures it (0: exact depth)")(
      "path", po::value(&o.path)->default_value(o.path),
      "viewpoints: sphere (spread around the object), orbit (one turn, a "
      "hand-held sequence), handheld (one turn, nearer and farther, swaying in fast "
      "turns), fastturns (the same swaying twice as far, 2.5 times as often: up to about 6 degrees "
      "a frame), walk (a depth camera carried inside the scene, e.g. --shape room) or "
      "stations (terrestrial scanners inside the scene, e.g. --shape room; width x "
      "height is a full turn x 160 degrees)")(
      "format", po::value(&o.format)->default_value(o.format),
      "ply (range grids, truth.conf), tum, redwood or 7scenes (a depth-image sequence: 16-bit "
      "PNG, poses, intrinsics), or ptx or e57 (one Leica PTX or ASTM E57 file of every station, "
      "truth.conf)")("scale", po::value(&o.scale)->default_value(o.scale),
                     "multiply the mesh's coordinates (e.g. to room size)")(
      "outliers", po::value(&s.outliers)->default_value(0.0), "fraction of outlier samples")(
      "patches", po::value(&s.patches)->default_value(0), "extraneous patches, one scan each")(
      "rot-deg", po::value(&s.rotDeg)->default_value(0.0), "pose perturbation: max angle per axis")(
      "trans-vox", po::value(&s.transVox)->default_value(0.0),
      "pose perturbation: max shift per axis, voxels")("seed", po::value(&s.seed)->default_value(1),
                                                       "random seed")(
      "ascii", po::bool_switch(&o.ascii), "write ASCII range grids (default binary)")(
      "big-endian", po::bool_switch(&o.bigEndian), "write big-endian binary range grids")(
      "texture", po::value(&s.texture)->default_value(0.0),
      "colour the surface with checks of this side (world units; 0: no colour): range grids and "
      "PTX get red green blue, sequences colour images (TUM rgb/, Redwood color/), truth.ply "
      "the checks' colour at its vertices")(
      "colour-shift", po::value(&s.colourShift)->default_value(0.0),
      "with --texture: the colour image misregistered with the depth by this many pixels along "
      "its rows, as a colour camera calibrated to about a pixel (pinhole views)")(
      "jpeg", po::bool_switch(&o.jpeg),
      "write sequences' colour images as JPEG (quality 95), as Open3D's recorder does")(
      "e57-coordinates", po::value(&o.e57Coordinates)->default_value(o.e57Coordinates),
      "--format e57: double, single, scaled (integers of 0.1 mm, in scan units 1e-4) or "
      "spherical (range, azimuth, elevation)")(
      "e57-loose", po::bool_switch(&o.e57Loose),
      "--format e57: the returns alone, without row and column indices")("out", po::value(&o.out),
                                                                         "output folder");
  addLimitOptions(d, o.limits, false);
  po::variables_map vm;
  const int parsed = parseCollectively(
      argc, argv, d, vm,
      "rangefuse scan --shape composite --views 24 --voxel 1 --noise 0.5 --out synth", "scan",
      comm);
  if (parsed >= 0) return parsed;
  return runOnRoot(comm, [&] { return run(o); });
}

}  // namespace rangefuse::cli
