#include "RunReport.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/MpiTraffic.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/register/PairOverlap.h"
#include "rangefuse/register/Stragglers.h"

using nlohmann::json;

namespace rangefuse {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

/// What the rank's peak was made of, MiB: the process before the run, each part the stages
/// account for when their sum peaked, and the rest (allocator slack, transient copies, what
/// no stage accounts for).
json memoryBreakdown() {
  const MemoryLedger& ledger = memoryLedger();
  json parts = {{"process", ledger.processBytes() / kMiB}};
  for (size_t p = 0; p < MemoryLedger::kParts; ++p)
    parts[heldName(static_cast<Held>(p))] = ledger.atPeak()[p] / kMiB;
  const double peak = static_cast<double>(peakMemoryMiB());
  parts["other"] = std::max(0.0, peak - (ledger.processBytes() + ledger.peakTotal()) / kMiB);
  return parts;
}

/// One rank's entry, as JSON text (gathered as bytes).
std::string rankEntry(MPI_Comm comm, const Progress& progress, const RankCounters& c) {
  const mpi::Traffic traffic = mpi::traffic();
  json stages = json::object();
  for (const auto& [name, seconds] : progress.stages()) stages[name] = seconds;
  return json{{"rank", mpi::rank(comm)},
              {"stage_seconds", stages},
              {"bricks", c.bricks},
              {"prisms", c.prisms},
              {"voxels_updated", c.voxelUpdates},
              {"voxel_updates_predicted", c.predictedUpdates},
              {"adding_seconds", c.addSeconds},
              {"planning_seconds", c.planSeconds},
              {"routing_seconds", c.routeSeconds},
              {"tracking_seconds",
               {{"reading", c.trackReadSeconds},
                {"fitting", c.trackFitSeconds},
                {"adding", c.trackAddSeconds}}},
              {"evaluated_points", c.evaluatedPoints},
              {"halo_bricks_received", c.haloBricks},
              {"triangles", c.triangles},
              {"routed_bytes_sent", c.routedBytes},
              {"peak_memory_mib", peakMemoryMiB()},
              {"mpi",
               {{"bytes_sent", traffic.bytesSent},
                {"bytes_received", traffic.bytesReceived},
                {"calls", traffic.calls}}},
              {"memory_at_peak_mib", memoryBreakdown()}}
      .dump();
}

/// A loose scan's loosest motion: a turn about an axis through a point, or a slide.
json looseJson(const LooseMotion& m) {
  const Eigen::Vector3d &a = m.axis, &p = m.through;
  json j = {{"kind", m.turn ? "turn" : "slide"},
            {"ways", m.looseWays},
            {"direction", {a.x(), a.y(), a.z()}}};
  if (m.turn) j["through"] = {p.x(), p.y(), p.z()};
  return j;
}

json registrationJson(RegistrationMode mode, const std::vector<RegistrationStep>& steps,
                      double voxel) {
  json fits = json::array();
  for (const auto& s : steps)
    fits.push_back({{"algorithm", toString(s.algorithm)},
                    {"round", s.round},
                    {"iteration", s.iteration},
                    {"scan", s.scan},
                    {"correspondences", s.correspondences},
                    {"rms", s.rms},
                    {"rotation_deg", s.rotationDeg},
                    {"translation", s.translation},
                    {"applied", s.applied}});
  for (size_t k = 0; k < steps.size(); ++k)
    if (steps[k].algorithm == FitAlgorithm::Others)
      fits[k]["others_motion"] = steps[k].othersMotion;
  // Each scan's last fit, and whether it is out of line with the others (Stragglers.h).
  const std::vector<ScanStanding> standings = lastStandings(steps), out = findStragglers(standings);
  const std::vector<RegistrationStep> others = findOthersStragglers(steps, voxel);
  json scans = json::array();
  for (const ScanStanding& s : standings) {
    scans.push_back({{"scan", s.scan},
                     {"rms", s.rms},
                     {"correspondences", s.correspondences},
                     {"rms_score", std::isfinite(s.rmsScore) ? json(s.rmsScore) : json(nullptr)},
                     {"overlap_share", s.overlapShare},
                     {"straggler",
                      std::any_of(out.begin(), out.end(),
                                  [&](const ScanStanding& o) { return o.scan == s.scan; }) ||
                          std::any_of(others.begin(), others.end(),
                                      [&](const RegistrationStep& o) { return o.scan == s.scan; })},
                     {"hold", s.loose.hold},
                     {"loose", s.loose.hold < kLooseHold}});
    if (s.loose.hold < kLooseHold) scans.back()["loose_motion"] = looseJson(s.loose);
    for (const RegistrationStep& o : steps)  // the check against the other scans alone
      if (o.algorithm == FitAlgorithm::Others && o.scan == s.scan)
        scans.back()["others_motion"] = o.othersMotion;
  }
  json pairs = json::array();
  for (const PairOverlap& p : pairOverlaps(steps))
    pairs.push_back({{"a", p.a}, {"b", p.b}, {"first", p.first}, {"last", p.last}});
  return {{"mode", toString(mode)}, {"fits", fits}, {"scans", scans}, {"pairs", pairs}};
}

}  // namespace

uint64_t peakMemoryMiB() {
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return static_cast<uint64_t>(u.ru_maxrss) / 1024;  // ru_maxrss is in KiB on Linux
}

/// The mesh written: its file and size, and with --fill-holes what closes its holes.
json meshJson(const std::string& file, const MeshPart& mesh) {
  json j = {{"file", file}, {"triangles", mesh.totalFaces}, {"vertices", mesh.totalVertices}};
  if (mesh.marksFilled) {
    j["filled_triangles"] = mesh.filledFaces;
    j["filled_area"] = mesh.filledArea;
  }
  return j;
}

void writeRunReport(const RunSettings& s, MPI_Comm comm, const Progress& progress,
                    const RankCounters& counters, const FusedField& field, const MeshPart& mesh,
                    const std::vector<RegistrationStep>& steps) {
  const std::map<size_t, std::string> all = mpi::gatherIndexed(
      {{static_cast<size_t>(mpi::rank(comm)), rankEntry(comm, progress, counters)}}, 0, comm);
  if (mpi::rank(comm) != 0) return;
  json ranks = json::array();
  for (const auto& [rank, entry] : all) ranks.push_back(json::parse(entry));
  json parameters = s.recorded.result;
  // The option keeps -1 (so a checkpoint's parameters compare as given); show what was used.
  if (s.field.quorum < 0) parameters["quorum_used"] = autoQuorum(field.scanCount);
  json report = {{"command", "fuse"},
                 {"inputs",
                  {{"scans", s.read.scans},
                   {"scan_count", field.scanCount},
                   {"scan_triangles", field.scanTriangles}}},
                 {"parameters", parameters},
                 {"ranks", mpi::size(comm)},
                 {"threads_per_rank", s.field.threads},
                 {"total_bricks", field.layout.totalBricks()},
                 {"wall_seconds", progress.elapsed()},
                 {"per_rank", ranks},
                 {"mesh", meshJson(s.outputs.out, mesh)},
                 {"registration", registrationJson(s.registration.mode, steps, s.field.voxel)}};
  if (field.tracking) report["tracking"] = field.tracking->toJson();
  io::writeJson(s.outputs.report, report);
}

}  // namespace rangefuse
