#include "rangefuse/fuse/RunSettings.h"

#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/fuse/FuseParameters.h"

namespace rangefuse {
namespace {

ReadSettings readSettings(const FuseOptions& o) {
  ReadSettings r;
  r.scans = o.scans;
  r.source = o.source;
  r.limits = o.limits;
  r.surface =
      surfaceOptions(o.surface, o.mergeCells, o.smoothNoise, o.voxel, o.method, o.fillHoles);
  r.eps = o.envelope * o.voxel;
  r.voxel = o.voxel;
  r.bandCells = static_cast<uint64_t>(o.bandCells);
  r.keepBytes = static_cast<uint64_t>(o.scanMemory * 1024 * 1024);
  r.threads = o.threads;
  return r;
}

FieldSettings fieldSettings(const FuseOptions& o) {
  FieldSettings f;
  f.method = o.method;
  f.voxel = o.voxel;
  f.envelope = o.envelope;
  f.brick = o.brick;
  f.maxVoxels = o.limits.maxVoxels;
  f.threads = o.threads;
  f.colour = o.colour;
  f.quorum = o.quorum;
  f.minViews = o.minViews;
  f.edgeAngle = o.edgeAngle;
  f.sameDistance = o.sameDistance;
  f.sameAngle = o.sameAngle;
  f.freeMargin = o.freeMargin;
  f.fillHoles = o.fillHoles;
  return f;
}

RegisterSettings registerSettings(const FuseOptions& o) {
  RegisterSettings r;
  r.mode = o.registration;
  r.anchor = o.anchor;
  r.controlStride = o.controlStride;
  r.maxIterations = o.maxIterations;
  r.maxRounds = o.maxRounds;
  r.roundTolerance = o.roundTolerance;
  r.field = o.registerField;
  r.solve = o.registerSolve;
  return r;
}

TrackSettings trackSettings(const FuseOptions& o) {
  TrackSettings t;
  t.track = o.track;
  t.firstPose = o.firstPose;
  t.minInliers = o.minInliers;
  t.maxStep = o.maxStep;
  t.skipLost = o.skipLost;
  t.follow = o.follow;
  t.followTimeout = o.followTimeout;
  t.previewEvery = o.previewEvery;
  return t;
}

OutputSettings outputSettings(const FuseOptions& o) {
  OutputSettings out;
  out.out = o.out;
  out.report = o.report;
  out.preview = o.preview;
  out.previewView = o.previewView;
  out.up = o.up;
  out.posesOut = o.posesOut;
  out.trajectoryOut = o.trajectoryOut;
  out.checkpoint = o.checkpoint;
  out.checkpointEvery = o.checkpointEvery;
  out.resume = o.resume;
  out.overwrite = o.overwrite;
  out.config = o.config;
  return out;
}

}  // namespace

SurfaceOptions surfaceOptions(const SurfaceOptions& base, double mergeCells, double smoothNoise,
                              double voxel, FieldMethod method, bool fillHoles) {
  SurfaceOptions s = base;
  s.mergeTarget = mergeCells * voxel;
  s.smoothTarget = smoothNoise * voxel;
  s.sightMap = methodInfo(method).hypotheses || fillHoles;
  return s;
}

RunSettings runSettings(const FuseOptions& o) {
  RunSettings s;
  s.read = readSettings(o);
  s.field = fieldSettings(o);
  s.registration = registerSettings(o);
  s.track = trackSettings(o);
  s.mesh =
      MeshSettings{o.minWeight, o.normals, o.threads, o.fillHoles, kCarveMarginVoxels * o.voxel};
  s.outputs = outputSettings(o);
  s.recorded.result = resultParameters(o);
  s.recorded.checkpointOnly = nlohmann::json::object();
  for (const FuseParameter& p : fuseParameters())
    if (p.recorded == Recorded::CheckpointOnly)
      s.recorded.checkpointOnly[p.key] = parameterJson(p, o);
  return s;
}

}  // namespace rangefuse
