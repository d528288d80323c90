#include "rangefuse/options/RunSettings.h"

#include "rangefuse/options/FuseParameters.h"

namespace rangefuse {
namespace {

ReadSettings readSettings(const FuseOptions& o) {
  const FieldSettings& f = o.field;
  ReadSettings r;
  r.scans = o.scans;
  r.source = o.source;
  r.limits = o.limits;
  r.surface = surfaceOptions(o);
  r.eps = f.eps();
  r.voxel = f.voxel;
  r.bandCells = static_cast<uint64_t>(o.bandCells);
  r.keepBytes = static_cast<uint64_t>(o.scanMemory * 1024 * 1024);
  r.threads = f.threads;
  return r;
}

}  // namespace

SurfaceOptions surfaceOptions(const FuseOptions& o) {
  const FieldSettings& f = o.field;
  SurfaceOptions s = o.surface;
  s.mergeTarget = o.mergeCells * f.voxel;
  s.smoothTarget = o.smoothNoise * f.voxel;
  s.flatTolerance = o.joinFlat * f.voxel;
  s.sightMap = methodInfo(f.method).hypotheses || f.fillHoles;
  return s;
}

RunSettings runSettings(const FuseOptions& o) {
  RunSettings s;
  s.read = readSettings(o);
  s.field = o.field;
  s.field.maxVoxels = o.limits.maxVoxels;
  s.registration = o.registration;
  s.track = o.stream;
  s.mesh = MeshSettings{o.minWeight, o.normals, o.field.threads, o.field.fillHoles,
                        kCarveMarginVoxels * o.field.voxel};
  s.outputs = o.outputs;
  s.recorded.result = resultParameters(o);
  s.recorded.checkpointOnly = nlohmann::json::object();
  for (const FuseParameter& p : fuseParameters())
    if (p.recorded == Recorded::CheckpointOnly)
      s.recorded.checkpointOnly[p.key] = parameterJson(p, o);
  return s;
}

}  // namespace rangefuse
