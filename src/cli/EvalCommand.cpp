#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/eval/ColourError.h"
#include "rangefuse/eval/Comparison.h"
#include "rangefuse/eval/PoseConsistency.h"
#include "rangefuse/eval/TrajectoryError.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/io/Trajectory.h"
#include "rangefuse/surface/ScanSurface.h"

namespace po = boost::program_options;
using nlohmann::json;

namespace rangefuse::cli {
namespace {

struct EvalOptions {
  std::string mesh, reference, seen, poses, referencePoses, jsonOut, trajectory;
  double voxel = 0, tau = 1, spurious = 3, nearEdge = 2;
  size_t samples = 200000;
  bool json = false, consistency = false;
  InputLimits limits;
  io::ScanSourceOptions source;
};

json statsJson(const DistanceStats& s) {
  return {{"mean", s.mean}, {"median", s.median}, {"p90", s.p90}, {"p99", s.p99}, {"max", s.max}};
}

void printStats(const char* name, const DistanceStats& s, double voxel) {
  std::printf(
      "%-13s mean %.5g  median %.5g  p90 %.5g  p99 %.5g  max %.5g   (voxels: mean %.3f  p99 "
      "%.3f)\n",
      name, s.mean, s.median, s.p90, s.p99, s.max, s.mean / voxel, s.p99 / voxel);
}

/// The cells (edge tau / 2) the scans of --seen cross, triangulated as fusion does but keeping
/// oblique triangles too (the yardstick should not be our own filter).
SeenCells seenCells(const EvalOptions& o) {
  SeenCells cells(o.tau * o.voxel / 2);
  SurfaceOptions surface;
  surface.minCosine = 0;
  for (const auto& s : io::readScanList(o.seen, o.limits, o.source).scans)
    cells.addSurface(triangulateGrid(io::readScanGrid(s, o.limits), surface), s.pose);
  return cells;
}

/// The colour comparison when both meshes are coloured (null, with a note, otherwise).
json colourReport(const TriangleMesh& mesh, const TriangleMesh& ref, const EvalOptions& o) {
  if (mesh.colours.empty() || ref.colours.empty()) {
    if (!o.json && mesh.colours.empty() != ref.colours.empty())
      std::printf("colour: not compared, %s has no vertex colours\n",
                  (mesh.colours.empty() ? o.mesh : o.reference).c_str());
    return nullptr;
  }
  const ColourComparison c = compareColours(mesh, ref, o.spurious * o.voxel, o.nearEdge * o.voxel);
  if (!o.json) {
    std::printf(
        "colour error  mean %.3f  median %.3f  p90 %.3f  p99 %.3f  (of 255, %zu vertices within "
        "%.3g voxels)\n",
        c.error.mean, c.error.median, c.error.p90, c.error.p99, c.vertices, o.spurious);
    std::printf(
        "edge contrast %.4f over %zu mesh edges across texture edges (1: as sharp as the "
        "reference)\n",
        c.edgeContrast, c.edges);
    std::printf(
        "colour error  near texture edges (within %.3g voxels) mean %.3f over %zu vertices; "
        "farther mean %.3f over %zu\n",
        o.nearEdge, c.nearEdgeError.mean, c.nearEdgeVertices, c.farEdgeError.mean,
        c.farEdgeVertices);
  }
  return {
      {"vertices", c.vertices},
      {"error", statsJson(c.error)},
      {"near_edge_voxels", o.nearEdge},
      {"near_edge", {{"vertices", c.nearEdgeVertices}, {"error", statsJson(c.nearEdgeError)}}},
      {"far_from_edge", {{"vertices", c.farEdgeVertices}, {"error", statsJson(c.farEdgeError)}}},
      {"edge_contrast", c.edgeContrast},
      {"edges", c.edges}};
}

json meshReport(const EvalOptions& o) {
  checkLimit("eval", "--samples", static_cast<double>(o.samples), o.limits.maxElements,
             "max-elements");
  const TriangleMesh mesh = io::readMeshPly(o.mesh, o.limits);
  const TriangleMesh ref = io::readMeshPly(o.reference, o.limits);
  if (mesh.faces.empty()) throw InputError(o.mesh + ": mesh has no triangles");
  if (ref.faces.empty()) throw InputError(o.reference + ": mesh has no triangles");
  CompareSettings s{o.tau * o.voxel, o.spurious * o.voxel, o.samples, 1};
  std::optional<SeenCells> seen;
  if (!o.seen.empty()) seen = seenCells(o);
  const MeshComparison c = compareMeshes(mesh, ref, s, seen ? &*seen : nullptr);
  if (!o.json) {
    std::printf("mesh %s (%zu triangles) against %s (%zu triangles), %zu samples each way\n",
                o.mesh.c_str(), mesh.faces.size(), o.reference.c_str(), ref.faces.size(),
                o.samples);
    if (seen)
      std::printf(
          "seen surface: %.4f of the reference's area lies within about %g voxel of a scan's "
          "surface of %s; completeness and recall count only it\n",
          c.seenFraction, o.tau, o.seen.c_str());
    printStats("accuracy", c.accuracy, o.voxel);
    printStats("completeness", c.completeness, o.voxel);
    std::printf("chamfer       %.5g (%.3f voxels)\n", c.chamfer, c.chamfer / o.voxel);
    std::printf("tau %.3g voxel: precision %.4f  recall %.4f  F-score %.4f\n", o.tau, c.precision,
                c.recall, c.fscore);
    std::printf("spurious area (> %.3g voxels from the reference): %.4f%%\n", o.spurious,
                100 * c.spuriousAreaFraction);
  }
  const json colour = colourReport(mesh, ref, o);
  return {{"colour", colour},
          {"mesh", o.mesh},
          {"reference", o.reference},
          {"voxel", o.voxel},
          {"samples", o.samples},
          {"tau_voxels", o.tau},
          {"accuracy", statsJson(c.accuracy)},
          {"completeness", statsJson(c.completeness)},
          {"chamfer", c.chamfer},
          {"precision", c.precision},
          {"recall", c.recall},
          {"fscore", c.fscore},
          {"spurious_voxels", o.spurious},
          {"spurious_area_fraction", c.spuriousAreaFraction},
          {"seen", o.seen},
          {"seen_fraction", c.seenFraction}};
}

std::vector<Eigen::Vector3d> scanPoints(const io::ConfScan& s) {
  if (!std::filesystem::exists(s.path)) return {};
  return io::readScanGrid(s).points;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

/// The best common rigid motion of all estimates and the scans' displacements once it is
/// removed: a group that drifted away from the reference frame but agrees with itself shows a
/// large motion and small displacements.
json commonMotionReport(const std::vector<Pose>& estimates, const std::vector<Pose>& references,
                        const std::vector<std::vector<Eigen::Vector3d>>& points,
                        const EvalOptions& o) {
  const Pose g = commonMotion(estimates, references, points);
  std::vector<double> disp;
  double moved = 0;
  size_t n = 0;
  for (size_t i = 0; i < estimates.size(); ++i) {
    const Pose moved_i = g * estimates[i];
    disp.push_back(comparePose(moved_i, references[i], points[i]).displacementMean);
    for (size_t k = 0; k < points[i].size(); k += 16, ++n) {
      const Eigen::Vector3d p = estimates[i].apply(points[i][k]);
      moved += (g.apply(p) - p).norm();
    }
  }
  moved = n > 0 ? moved / n : 0;
  const double worst = disp.empty() ? 0 : *std::max_element(disp.begin(), disp.end());
  if (!o.json)
    std::printf(
        "common motion %.4f voxels (mean over points); without it: median displacement %.4f, "
        "worst %.4f voxels\n",
        moved / o.voxel, median(disp) / o.voxel, worst / o.voxel);
  return {{"mean_motion", moved},
          {"point_displacement_mean", {{"median", median(disp)}, {"max", worst}}}};
}

/// Per scan, how far its estimated pose (after the common motion) leaves it from the surfaces
/// the other scans give at their reference poses, beside the same at its own reference pose:
/// a pose off along a motion the surfaces do not hold (a turn about a symmetry axis) leaves
/// the two alike, and keeps its partners (vertices with an overlapping vertex in another scan;
/// a scan moved off the surface loses them). Empty when a scan's file is missing.
json surfaceReport(const std::vector<const io::ConfScan*>& scans,
                   const std::vector<Pose>& estimates, const std::vector<Pose>& references,
                   const std::vector<std::vector<Eigen::Vector3d>>& points, const EvalOptions& o) {
  // Two surfaces a scan (points, normals, trees at both poses): 50 M points take about 10 GB.
  constexpr size_t kMostPoints = 50'000'000;
  size_t total = 0;
  for (const auto& p : points) {
    if (p.empty()) return json::array();
    total += p.size();
  }
  if (total > kMostPoints) {
    if (!o.json)
      std::printf("surface check left out: %zu points (more than %zu)\n", total, kMostPoints);
    return json::array();
  }
  const Pose g = commonMotion(estimates, references, points);
  std::vector<ScanSurface> atReference, atEstimate;
  for (size_t i = 0; i < scans.size(); ++i) {
    const RangeGrid grid = io::readScanGrid(*scans[i], o.limits);
    atReference.push_back(buildScanSurface(grid, references[i], {}));
    const Pose moved = g * estimates[i];
    atEstimate.push_back(buildScanSurface(grid, moved, {}));
  }
  // Pairs up to 3 voxels apart along the normal: a scan a voxel or two off still has partners.
  const ConsistencySettings settings{3 * o.voxel, 2 * o.voxel};
  const auto est = poseConsistency(atEstimate, atReference, settings),
             ref = poseConsistency(atReference, settings);
  if (!o.json)
    std::printf("%-24s %18s %20s %16s\n", "scan", "surface rms (vox)", "at reference (vox)",
                "partners kept");
  json out = json::array();
  for (size_t i = 0; i < scans.size(); ++i) {
    const double kept = ref[i].pairs > 0 ? static_cast<double>(est[i].pairs) / ref[i].pairs : 0;
    out.push_back({{"name", scans[i]->name},
                   {"rms", est[i].rms},
                   {"reference_rms", ref[i].rms},
                   {"partners", est[i].pairs},
                   {"reference_partners", ref[i].pairs}});
    if (!o.json)
      std::printf("%-24s %18.4f %20.4f %16.3f\n", scans[i]->name.c_str(), est[i].rms / o.voxel,
                  ref[i].rms / o.voxel, kept);
  }
  return out;
}

/// What identifies a scan across pose lists: its file, resolved, with a PTX scan's #K; else
/// its name.
std::string scanKey(const io::ConfScan& s) {
  if (s.path.empty()) return s.name;
  const size_t hash = s.name.rfind('#');
  const std::string part =
      hash != std::string::npos && s.path.find('#') == std::string::npos ? s.name.substr(hash) : "";
  return std::filesystem::weakly_canonical(s.path).string() + part;
}

json poseReport(const EvalOptions& o) {
  const io::ConfFile est = io::readScanList(o.poses, o.limits, o.source),
                     ref = io::readScanList(o.referencePoses, o.limits, o.source);
  // A scan is the same file in both lists, whatever each list calls it (a .conf names files
  // relative to its own folder).
  std::map<std::string, const io::ConfScan*> byName;
  for (const auto& s : ref.scans) byName[scanKey(s)] = &s;
  json scans = json::array();
  std::vector<double> rot, trans, disp;
  std::vector<Pose> estimates, references;
  std::vector<std::vector<Eigen::Vector3d>> points;
  std::vector<const io::ConfScan*> refScans;
  if (!o.json)
    std::printf("%-24s %12s %14s %16s %16s\n", "scan", "rot (deg)", "trans (vox)",
                "disp mean (vox)", "disp max (vox)");
  for (const auto& s : est.scans) {
    auto it = byName.find(scanKey(s));
    if (it == byName.end())
      throw InputError(o.referencePoses + ": has no scan named '" + s.name + "'");
    points.push_back(scanPoints(*it->second));
    refScans.push_back(it->second);
    estimates.push_back(s.pose);
    references.push_back(it->second->pose);
    const PoseError e = comparePose(s.pose, references.back(), points.back());
    rot.push_back(e.rotationDeg);
    trans.push_back(e.translation);
    disp.push_back(e.displacementMean);
    scans.push_back({{"name", s.name},
                     {"rotation_deg", e.rotationDeg},
                     {"translation", e.translation},
                     {"point_displacement_mean", e.displacementMean},
                     {"point_displacement_max", e.displacementMax},
                     {"points", e.points}});
    if (!o.json)
      std::printf("%-24s %12.5f %14.4f %16.4f %16.4f\n", s.name.c_str(), e.rotationDeg,
                  e.translation / o.voxel, e.displacementMean / o.voxel,
                  e.displacementMax / o.voxel);
  }
  auto summary = [&](const std::vector<double>& v) {
    return json{{"median", median(v)},
                {"max", v.empty() ? 0 : *std::max_element(v.begin(), v.end())}};
  };
  if (!o.json)
    std::printf("median rotation %.5f deg, translation %.4f voxels, displacement %.4f voxels\n",
                median(rot), median(trans) / o.voxel, median(disp) / o.voxel);
  const json common = commonMotionReport(estimates, references, points, o);
  const json surface = surfaceReport(refScans, estimates, references, points, o);
  return {{"poses", o.poses},
          {"common_motion", common},
          {"surface", surface},
          {"reference_poses", o.referencePoses},
          {"voxel", o.voxel},
          {"scans", scans},
          {"rotation_deg", summary(rot)},
          {"translation", summary(trans)},
          {"point_displacement_mean", summary(disp)}};
}

/// Per pair of scans that overlap (kMinPartners or more vertices with a partner, both ways
/// together): partners, the share of both scans' measured vertices they are, and their RMS.
/// Poses that slide scans along each other keep the RMS but lose partners and pairs.
json pairOverlap(const io::ConfFile& conf, const std::vector<ScanConsistency>& c,
                 const EvalOptions& o) {
  constexpr size_t kMinPartners = 10;
  json out = json::array();
  if (!o.json)
    std::printf("%-24s %-24s %10s %9s %14s\n", "scan", "scan", "partners", "overlap", "rms (vox)");
  for (size_t i = 0; i < c.size(); ++i)
    for (size_t j = i + 1; j < c.size(); ++j) {
      const size_t n = c[i].pairsWith[j] + c[j].pairsWith[i];
      if (n < kMinPartners) continue;
      const double share =
          static_cast<double>(n) / static_cast<double>(c[i].sampled + c[j].sampled);
      const double squares = c[i].rmsWith[j] * c[i].rmsWith[j] * c[i].pairsWith[j] +
                             c[j].rmsWith[i] * c[j].rmsWith[i] * c[j].pairsWith[i];
      const double rms = std::sqrt(squares / static_cast<double>(n));
      out.push_back({{"a", conf.scans[i].name},
                     {"b", conf.scans[j].name},
                     {"partners", n},
                     {"overlap", share},
                     {"rms", rms}});
      if (!o.json)
        std::printf("%-24s %-24s %10zu %9.4f %14.4f\n", conf.scans[i].name.c_str(),
                    conf.scans[j].name.c_str(), n, share, rms / o.voxel);
    }
  if (!o.json)
    std::printf("overlapping scan pairs %zu of %zu (%zu or more partners)\n", out.size(),
                c.size() * (c.size() - 1) / 2, kMinPartners);
  return out;
}

/// The scans of --poses, in the world, agreeing with one another (no reference needed).
json consistencyReport(const EvalOptions& o) {
  const io::ConfFile conf = io::readScanList(o.poses, o.limits, o.source);
  std::vector<ScanSurface> world;
  for (const auto& s : conf.scans)
    world.push_back(buildScanSurface(io::readScanGrid(s, o.limits), s.pose, {}));
  const ConsistencySettings settings{2 * o.voxel, o.voxel};
  const std::vector<ScanConsistency> c = poseConsistency(world, settings);
  json scans = json::array();
  double sum = 0;
  size_t pairs = 0;
  if (!o.json) std::printf("%-24s %12s %18s\n", "scan", "pairs", "rms to others (vox)");
  for (size_t i = 0; i < c.size(); ++i) {
    scans.push_back({{"name", conf.scans[i].name}, {"pairs", c[i].pairs}, {"rms", c[i].rms}});
    sum += c[i].rms * c[i].rms * static_cast<double>(c[i].pairs);
    pairs += c[i].pairs;
    if (!o.json)
      std::printf("%-24s %12zu %18.4f\n", conf.scans[i].name.c_str(), c[i].pairs,
                  c[i].rms / o.voxel);
  }
  const double rms = pairs > 0 ? std::sqrt(sum / static_cast<double>(pairs)) : 0.0;
  if (!o.json)
    std::printf("point-to-plane rms between scans %.5g (%.4f voxels) over %zu pairs\n", rms,
                rms / o.voxel, pairs);
  const json overlap = pairOverlap(conf, c, o);
  return {{"poses", o.poses},
          {"voxel", o.voxel},
          {"scans", scans},
          {"rms", rms},
          {"pairs", pairs},
          {"scan_pairs", overlap},
          {"overlapping_scan_pairs", overlap.size()}};
}

/// The estimate against the reference, matched by time; when exactly one of them is a .log
/// (frame indices, no times) and times match too few poses, matched by index instead.
TrajectoryError compareTrajectoryFiles(const std::string& estimate, const std::string& reference) {
  const auto est = io::readTrajectory(estimate), ref = io::readTrajectory(reference);
  if (io::isLogTrajectory(estimate) == io::isLogTrajectory(reference))
    return compareTrajectories(est, ref);
  try {
    return compareTrajectories(est, ref);
  } catch (const InputError&) {
    return compareTrajectories(est, ref, 0.02, 1.0, PoseMatching::byIndex);
  }
}

/// --trajectory against --reference: ATE and RPE as the TUM benchmark defines them.
json trajectoryReport(const EvalOptions& o) {
  if (o.reference.empty())
    throw InputError("eval: --trajectory needs --reference (the true trajectory)");
  const TrajectoryError e = compareTrajectoryFiles(o.trajectory, o.reference);
  const bool byIndex = e.matching == PoseMatching::byIndex;
  json j = {{"trajectory", o.trajectory},
            {"reference", o.reference},
            {"matched_by", byIndex ? "index" : "time"},
            {"units", "m"},
            {"matched", e.matched},
            {"ate_rmse", e.ateRmse},
            {"ate_mean", e.ateMean},
            {"ate_max", e.ateMax},
            {"rpe_pairs", e.rpePairs},
            {"rpe_translation_rmse_per_s", e.rpeTranslationRmse},
            {"rpe_rotation_rmse_deg_per_s", e.rpeRotationRmseDeg}};
  if (!o.json) {
    if (byIndex)
      std::printf(
          "matched by index: %s has frame numbers, not times, and by time (frame k at "
          "k/%g s) too few poses matched\n",
          io::isLogTrajectory(o.trajectory) ? o.trajectory.c_str() : o.reference.c_str(),
          io::kRedwoodFrameRate);
    std::printf("poses matched      %zu of %zu by %s\n", e.matched, e.estimated,
                byIndex ? "index" : "time");
    std::printf("ATE RMSE           %.6g m (mean %.6g m, max %.6g m)\n", e.ateRmse, e.ateMean,
                e.ateMax);
    if (e.rpePairs > 0)
      std::printf("RPE over 1 s       %.6g m per s, %.4g deg per s (%zu pairs)\n",
                  e.rpeTranslationRmse, e.rpeRotationRmseDeg, e.rpePairs);
  }
  return j;
}

/// --json-out checked against every file eval reads, before any is.
void refuseOverwrite(const EvalOptions& o) {
  if (o.jsonOut.empty()) return;
  io::FileRoles files;
  files.outputs = io::outputWithTemporary("JSON report", o.jsonOut);
  files.inputs = {{"mesh", o.mesh},
                  {"reference", o.reference},
                  {"seen scans", o.seen},
                  {"poses", o.poses},
                  {"reference poses", o.referencePoses},
                  {"trajectory", o.trajectory}};
  io::refuseOverlaps(files);
  io::requireExtension(o.jsonOut, "JSON report", {".json"});
}

int run(const EvalOptions& o) {
  refuseOverwrite(o);
  if (!o.trajectory.empty()) {
    const json report = trajectoryReport(o);
    if (o.json) std::cout << report.dump(2) << std::endl;
    if (!o.jsonOut.empty()) io::writeJson(o.jsonOut, report);
    return 0;
  }
  if (!(o.voxel > 0)) throw InputError("eval: --voxel must be positive");
  const bool meshes = !o.mesh.empty() || !o.reference.empty();
  const bool poses = !o.poses.empty() || !o.referencePoses.empty();
  if (o.consistency && (o.poses.empty() || meshes || !o.referencePoses.empty()))
    throw InputError("eval: --consistency goes with --poses alone");
  if (!o.consistency && meshes == poses)
    throw InputError("eval: give either --mesh and --reference, or --poses and --reference-poses");
  if (meshes && (o.mesh.empty() || o.reference.empty()))
    throw InputError("eval: --mesh and --reference go together");
  if (!o.consistency && poses && (o.poses.empty() || o.referencePoses.empty()))
    throw InputError("eval: --poses and --reference-poses go together");
  const json report = o.consistency ? consistencyReport(o) : meshes ? meshReport(o) : poseReport(o);
  if (o.json) std::cout << report.dump(2) << std::endl;
  if (!o.jsonOut.empty()) io::writeJson(o.jsonOut, report);
  return 0;
}

}  // namespace

int evalCommand(int argc, char** argv, MPI_Comm comm) {
  EvalOptions o;
  po::options_description d(
      "rangefuse eval: a mesh against a reference mesh, or poses against reference poses");
  d.add_options()("help,h", "show this help");
  po::options_description meshes("Meshes");
  meshes.add_options()("mesh", po::value(&o.mesh), "mesh to judge (PLY)")(
      "reference", po::value(&o.reference),
      "reference mesh (PLY), or with --trajectory the true trajectory")(
      "voxel", po::value(&o.voxel), "voxel size (model units): results are also given in voxels")(
      "seen", po::value(&o.seen),
      "scan list (.conf, .ptx or sequence folder, with true poses): completeness and recall "
      "count only the reference surface within about --tau of its triangulated scans, the part "
      "the scanners saw")("tau", po::value(&o.tau)->default_value(1.0),
                          "F-score threshold, voxels")(
      "spurious", po::value(&o.spurious)->default_value(3.0), "spurious-area distance, voxels")(
      "near-edge", po::value(&o.nearEdge)->default_value(2.0),
      "colour: vertices this near a texture edge of the reference are reported apart, voxels")(
      "samples", po::value(&o.samples)->default_value(200000), "area-weighted samples per mesh");
  po::options_description poses("Poses and trajectories");
  poses.add_options()("poses", po::value(&o.poses), "estimated poses (.conf)")(
      "reference-poses", po::value(&o.referencePoses),
      "reference poses (.conf); its scan files give the points")(
      "consistency", po::bool_switch(&o.consistency),
      "with --poses alone: how well the scans agree with one another (point-to-plane RMS to "
      "the nearest vertex of each other scan, no field involved)")(
      "trajectory", po::value(&o.trajectory),
      "estimated camera trajectory (TUM text, or .log): ATE and RPE against --reference");
  po::options_description output("Output");
  output.add_options()("json", po::bool_switch(&o.json),
                       "print one JSON object instead of the table")(
      "json-out", po::value(&o.jsonOut), "also write the JSON object to this file");
  po::options_description reading("Reading scan lists");
  addSourceOptions(reading, o.source, "--seen, --poses and --reference-poses");
  po::options_description limits("Input limits");
  addLimitOptions(limits, o.limits, false);
  d.add(meshes).add(poses).add(output).add(reading).add(limits);
  po::variables_map vm;
  const int parsed = parseCollectively(argc, argv, d, vm,
                                       "rangefuse eval --mesh out/bunny.ply --reference "
                                       "tests/data/bunny/bun_zipper.ply --voxel 0.001",
                                       "eval", comm);
  if (parsed >= 0) return parsed;
  return runOnRoot(comm, [&] { return run(o); });
}

}  // namespace rangefuse::cli
