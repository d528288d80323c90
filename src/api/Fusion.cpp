#include <hdf5.h>

#include <cmath>
#include <cstdlib>
#include <optional>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/Digest.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/io/Trajectory.h"
#include "rangefuse/mesh/PartStitching.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/MpiStart.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/parallelio/Checkpoint.h"
#include "rangefuse/pipeline/Checkpointing.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/pipeline/FinishRun.h"
#include "rangefuse/rangefuse.h"
#include "rangefuse/track/StreamColour.h"
#include "rangefuse/track/TrackedFrames.h"

namespace rangefuse {
namespace {

/// The command's default --scan-memory, which the library does not let callers set.
const double kKeepMiB = FuseOptions{}.scanMemory;

/// This process alone, MPI started first when no one has (and finished when the program ends).
MPI_Comm selfComm() {
  int started = 0;
  MPI_Initialized(&started);
  if (!started) {
    mpi::start(nullptr, nullptr);
    std::atexit([] {
      int finished = 0;
      MPI_Finalized(&finished);
      if (!finished) MPI_Finalize();
    });
  }
  return MPI_COMM_SELF;
}

/// The grid's shape and indices, so that a grid made by hand cannot lead the field astray.
void checkGrid(const RangeGrid& g, const std::string& name) {
  if (g.rows <= 0 || g.cols <= 0 || g.cell.size() != size_t(g.rows) * size_t(g.cols))
    throw InputError(name + ": the grid's cells are not rows x cols (" + std::to_string(g.rows) +
                     " x " + std::to_string(g.cols) + ", " + std::to_string(g.cell.size()) +
                     " cells)");
  for (const int32_t c : g.cell)
    if (c < -1 || c >= static_cast<int64_t>(g.points.size()))
      throw InputError(name + ": a cell names point " + std::to_string(c) + " of " +
                       std::to_string(g.points.size()));
  for (const Eigen::Vector3d& p : g.points)
    if (!p.allFinite()) throw InputError(name + ": a point is not finite");
  if (!g.colours.empty() && g.colours.size() != g.points.size())
    throw InputError(name + ": " + std::to_string(g.colours.size()) + " colours for " +
                     std::to_string(g.points.size()) + " points");
}

/// The content hash of a frame held in memory, as checkpoints record a scan file's.
std::string frameHash(const io::MemoryScan& m) {
  uint64_t h = io::kFnvOffset;
  h = io::fnv1a64(m.grid.points.data(), m.grid.points.size() * sizeof(Eigen::Vector3d), h);
  h = io::fnv1a64(m.grid.cell.data(), m.grid.cell.size() * sizeof(int32_t), h);
  h = io::fnv1a64(m.depth.counts.data(), m.depth.counts.size() * sizeof(uint16_t), h);
  h = io::fnv1a64(m.colour.rgb.data(), m.colour.rgb.size(), h);
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

/// The settings as the command's checkpoints record its options.
nlohmann::json recordedSettings(const FieldSettings& f, const SurfaceOptions& surface) {
  FuseOptions o;
  o.field = f;
  o.surface = surface;
  o.mergeCells = surface.mergeTarget / f.voxel, o.smoothNoise = surface.smoothTarget / f.voxel;
  o.joinFlat = surface.flatTolerance / f.voxel;
  return resultParameters(o);
}

}  // namespace

struct Fusion::State {
  FieldSettings field;
  SurfaceOptions surface;
  MPI_Comm comm = MPI_COMM_SELF;
  std::shared_ptr<io::ConfFile> list = std::make_shared<io::ConfFile>();
  std::unique_ptr<internal::TrackedFrames> stream;  ///< set once a frame is tracked
  ColourKind trackedColour = ColourKind::none;      ///< what the tracked frames carry
  bool givenUp = false;                             ///< the stream was given up
  std::unique_ptr<BrickStore> resumed;              ///< a checkpoint's finished field
  /// Per frame: the content hash of a tracked frame whose images were let go of; empty for
  /// the others, hashed when a checkpoint is written (most fusions never write one).
  std::vector<std::string> hashes;
  size_t lastFused = 0;  ///< the tracked frame whose images the next frame's motion needs

  ReadSettings read() const {
    ReadSettings r;
    r.scans = "frames";
    r.list = list;
    r.limits.maxVoxels = field.maxVoxels;  // the command sets both from --max-voxels
    r.surface = surface;
    r.eps = field.eps();
    r.voxel = field.voxel;
    r.keepBytes = static_cast<uint64_t>(kKeepMiB * 1024 * 1024);
    r.threads = field.threads;
    return r;
  }

  /// Collective: the field of every frame at its pose (tracked frames at their tracked poses,
  /// the lost left out). Throws InputError with the failing rank's message.
  FusedField fuse(const mpi::CapturedFailure& failure) const {
    Progress quiet(comm, Verbosity::quiet);
    LoadedScans scans;
    FusedField fused;
    RankCounters counters;
    const std::vector<Pose>* poses = stream ? &stream->poses() : nullptr;
    const std::vector<char>* lost = stream ? &stream->lost() : nullptr;
    if (!buildStreamed(read(), field, comm, quiet, scans, fused, counters, poses, lost))
      throw InputError(failure.message());
    return fused;
  }

  std::string nameOf(const std::string& given) const {
    return given.empty() ? "frame_" + std::to_string(list->scans.size()) : given;
  }

  /// A frame read when the field is built, by the rank whose share it is.
  void add(io::MemoryScan&& frame, std::optional<io::DepthCamera> camera, const Pose& pose,
           const std::string& name) {
    io::ConfScan scan;
    scan.name = scan.path = name;
    scan.pose = pose;
    scan.depth = camera;
    hashes.emplace_back();
    scan.memory = std::make_shared<const io::MemoryScan>(std::move(frame));
    list->scans.push_back(std::move(scan));
  }

  /// A prism stream's field is its mesh, so of its images only the last fused frame's are read
  /// again (for the next frame's pixel motion); other methods fuse every frame again at the end.
  void letGoOfTracked(size_t i, bool fused) {
    if (field.method != FieldMethod::Prism || i == 0) return;
    const size_t drop = fused ? lastFused : i;
    if (fused) lastFused = i;
    hashes[drop] = frameHash(*list->scans[drop].memory);
    stream->forget(drop);
    list->scans[drop].memory.reset();
  }

  /// Collective: each frame's content hash, the scan files' read now (each by one rank).
  std::vector<std::string> contentHashes() const {
    std::vector<std::string> out = hashes;
    std::vector<std::string> paths;
    std::vector<size_t> files;
    for (size_t i = 0; i < out.size(); ++i) {
      if (!out[i].empty()) continue;
      const io::ConfScan& c = list->scans[i];
      if (c.memory)
        out[i] = frameHash(*c.memory);
      else
        files.push_back(i), paths.push_back(c.path);
    }
    if (files.empty()) return out;
    const std::vector<std::string> read = hashScans(paths, comm);
    for (size_t k = 0; k < files.size(); ++k) out[files[k]] = read[k];
    return out;
  }
};

const char* libraryVersion() {
  return RANGEFUSE_VERSION;
}

SurfaceOptions defaultSurface(const FieldSettings& field) {
  FuseOptions command;  // the command's defaults
  command.field = field;
  return surfaceOptions(command);
}

Fusion::Fusion(const FieldSettings& field, MPI_Comm comm)
    : Fusion(field, defaultSurface(field), comm) {}

Fusion::Fusion(const FieldSettings& field, const SurfaceOptions& surface, MPI_Comm comm)
    : state_(std::make_unique<State>()) {
  // HDF5 would print its whole error stack; its failures reach the caller as InputError.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  field.validate();
  State& s = *state_;
  s.comm = comm == MPI_COMM_NULL ? selfComm() : comm;
  s.field = field;
  if (s.field.threads <= 0) s.field.threads = threadsPerRank(s.comm);
  s.surface = surface;
}

Fusion::~Fusion() = default;
Fusion::Fusion(Fusion&&) noexcept = default;
Fusion& Fusion::operator=(Fusion&&) noexcept = default;

void Fusion::addGrid(RangeGrid grid, const Pose& pose, const std::string& name) {
  const std::string n = state_->nameOf(name);
  refuseResumed(n);
  if (state_->stream) throw InputError(n + ": this fusion tracks its frames; add none with a pose");
  checkGrid(grid, n);
  const Pose placed = rigidPose(pose, n);
  io::MemoryScan frame;
  frame.grid = std::move(grid);
  state_->add(std::move(frame), std::nullopt, placed, n);
}

void Fusion::addScans(const std::string& path, const io::ScanSourceOptions& source) {
  State& s = *state_;
  refuseResumed(path);
  source.validate();
  if (s.stream) throw InputError(path + ": this fusion tracks its frames; add none with a pose");
  mpi::CapturedFailure failure;
  io::ConfFile conf;
  if (!mpi::collectively(s.comm, [&] {
        conf = io::readScanList(path, s.read().limits, source);
        if (!conf.posed)
          throw InputError(path +
                           ": a depth stream without a trajectory has no poses to place "
                           "its frames: track them (Fusion::track)");
      }))
    throw InputError(failure.message());
  for (io::ConfScan& c : conf.scans) {
    s.list->scans.push_back(std::move(c));
    s.hashes.emplace_back();
  }
}

namespace {

/// A depth image (and its colour, when given) checked against its camera, kept as a frame.
io::MemoryScan depthFrame(io::DepthImage&& depth, const io::DepthCamera& camera,
                          const Image* colour, const std::string& n) {
  if (depth.width <= 0 || depth.height <= 0 ||
      depth.counts.size() != size_t(depth.width) * size_t(depth.height))
    throw InputError(n + ": the depth image's counts are not width x height");
  if ((camera.width && camera.width != depth.width) ||
      (camera.height && camera.height != depth.height))
    throw InputError(n + ": the depth image is " + std::to_string(depth.width) + " x " +
                     std::to_string(depth.height) + ", the camera's " +
                     std::to_string(camera.width) + " x " + std::to_string(camera.height));
  if (!(camera.fx > 0) || !(camera.fy > 0) || !(camera.unit > 0))
    throw InputError(n + ": the camera needs positive focal lengths and depth unit");
  io::ScanSourceOptions cut;  // the command's check of --depth-max
  cut.depthMax = camera.depthMax;
  cut.validate();
  if (colour && (colour->width != depth.width || colour->height != depth.height ||
                 colour->rgb.size() != size_t(colour->width) * size_t(colour->height) * 3))
    throw InputError(n + ": the colour image is " + std::to_string(colour->width) + " x " +
                     std::to_string(colour->height) + " (" + std::to_string(colour->rgb.size()) +
                     " bytes), the depth image " + std::to_string(depth.width) + " x " +
                     std::to_string(depth.height));
  io::MemoryScan frame;
  frame.depth = std::move(depth);
  if (colour) frame.colour = *colour;
  return frame;
}

}  // namespace

void Fusion::addDepth(io::DepthImage depth, const io::DepthCamera& camera,
                      const Pose& cameraToWorld, const Image* colour, const std::string& name) {
  const std::string n = state_->nameOf(name);
  refuseResumed(n);
  const Pose placed = rigidPose(cameraToWorld, n);
  if (state_->stream) throw InputError(n + ": this fusion tracks its frames; add none with a pose");
  io::MemoryScan frame = depthFrame(std::move(depth), camera, colour, n);
  state_->add(std::move(frame), camera, io::scanPose(placed), n);
}

TrackedFrame Fusion::track(io::DepthImage depth, const io::DepthCamera& camera, const Image* colour,
                           double time, const std::string& name) {
  State& s = *state_;
  const std::string n = s.nameOf(name);
  refuseResumed(n);
  if (s.givenUp) throw InputError(n + ": this fusion's stream was given up; start another");
  if (!s.stream && !s.list->scans.empty())
    throw InputError(n + ": this fusion was given frames with their poses; track in another");
  // The stream's colour is its first frame's: every later frame brings it too.
  const ColourKind kind =
      s.stream ? s.trackedColour : streamColour(s.field, {{n}, {colour != nullptr}, false}, n);
  if (kind == ColourKind::rgb && !colour)
    throw InputError(n + ": has no colour image, but the stream's first frame had one");
  io::MemoryScan frame =
      depthFrame(std::move(depth), camera, kind == ColourKind::rgb ? colour : nullptr, n);
  s.add(std::move(frame), camera, Pose{}, n);
  s.list->scans.back().time =
      std::isnan(time) ? double(s.list->scans.size() - 1) / io::kRedwoodFrameRate : time;
  mpi::CapturedFailure failure;
  try {
    if (!s.stream) {
      s.stream = std::make_unique<internal::TrackedFrames>(s.read(), s.field, kind, s.comm);
      s.trackedColour = kind;
    }
    const FrameReport r = s.stream->track();
    const size_t i = s.list->scans.size() - 1;
    s.list->scans[i].pose = s.stream->poses()[i];
    s.letGoOfTracked(i, r.fused);
    return TrackedFrame{io::cameraPose(s.stream->poses()[i]), r.fused, r.inliers, r.rms, r.why};
  } catch (const mpi::Reported&) {
    s.givenUp = true;
    throw InputError(!failure.message().empty() ? failure.message()
                     : s.stream                 ? n + ": " + s.stream->failure()
                                                : n + ": tracking failed");
  }
}

Fusion::Fusion(std::unique_ptr<State> state) : state_(std::move(state)) {}

namespace {

/// A checkpoint's path checked before any work: its name, its folder, and that it is none of
/// the files the frames were read from (Fusion::addScans).
void checkCheckpointPath(const std::string& path, const io::ConfFile& frames) {
  io::FileRoles files;
  files.outputs = io::outputWithTemporary("checkpoint", path);
  for (const io::ConfScan& c : frames.scans)
    if (!c.memory) files.inputs.push_back({"frame's file", c.path});
  io::refuseOverlaps(files);
  io::checkWritable(path, "checkpoint");
  io::requireExtension(path, "checkpoint", {".h5", ".hdf5"});
}

}  // namespace

void Fusion::saveCheckpoint(const std::string& path) {
  State& s = *state_;
  if (s.resumed)
    throw InputError(path + ": this fusion was resumed; its checkpoint is the one it read");
  if (s.list->scans.empty()) throw InputError("Fusion: no frames to checkpoint");
  mpi::CapturedFailure failure;
  if (!mpi::collectively(s.comm, [&] { checkCheckpointPath(path, *s.list); }))
    throw InputError(failure.message());
  FusedField field;
  const BrickStore* store = nullptr;
  if (s.stream && s.field.method == FieldMethod::Prism) {
    store = &s.stream->store();
  } else {
    field = s.fuse(failure);
    store = field.store.get();
  }
  io::CheckpointMeta meta;
  meta.parameters = recordedSettings(s.field, s.surface);
  if (!mpi::collectively(s.comm, [&] { meta.scanHashes = s.contentHashes(); }))
    throw InputError(failure.message());
  for (const io::ConfScan& c : s.list->scans) {
    meta.scanNames.push_back(c.name);
    meta.poses.push_back(c.pose);
  }
  meta.progress = {{"stage", "field"}};
  meta.hasField = true;
  meta.grid = store->layout().grid;
  if (!mpi::collectively(s.comm, [&] { io::writeCheckpoint(path, meta, store, s.comm); }))
    throw InputError(failure.message());
}

Fusion Fusion::resume(const std::string& path, MPI_Comm comm) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // as in the constructor
  auto s = std::make_unique<State>();
  s->comm = comm == MPI_COMM_NULL ? selfComm() : comm;
  mpi::CapturedFailure failure;
  io::CheckpointMeta meta;
  BrickLayout layout;
  if (!mpi::collectively(s->comm, [&] {
        meta = io::readCheckpointMeta(path, s->comm);
        if (!meta.hasField || meta.progress.value("stage", "") != "field")
          throw InputError(path + ": holds no finished field (stage '" +
                           meta.progress.value("stage", "") + "'); resume it with rangefuse fuse");
        s->resumed = io::readCheckpointField(path, meta, layout, s->comm);
      }))
    throw InputError(failure.message());
  s->field.voxel = meta.grid.voxel;
  s->field.threads = threadsPerRank(s->comm);
  if (meta.parameters.contains("method"))
    s->field.method = parseFieldMethod("method", meta.parameters["method"].get<std::string>());
  for (size_t i = 0; i < meta.scanNames.size(); ++i) {
    io::ConfScan c;
    c.name = c.path = meta.scanNames[i];
    c.pose = meta.poses[i];
    s->list->scans.push_back(std::move(c));
  }
  return Fusion(std::move(s));
}

void Fusion::refuseResumed(const std::string& name) const {
  if (state_->resumed)
    throw InputError(name +
                     ": this fusion holds a checkpoint's finished field; it takes no frames");
}

size_t Fusion::frames() const {
  return state_->list->scans.size();
}

MeshPart Fusion::meshPart() {
  const State& s = *state_;
  if (s.resumed) return extractDistributedMesh(*s.resumed, 0, s.comm, nullptr, s.field.threads);
  if (s.list->scans.empty()) throw InputError("Fusion: no frames to fuse");
  if (s.givenUp) throw InputError("Fusion: the stream was given up; its field is not kept");
  mpi::CapturedFailure failure;
  if (s.stream && s.field.fillHoles)
    throw InputError("Fusion: fillHoles: tracked frames have no sight maps to carve with");
  if (s.stream && s.field.method == FieldMethod::Prism) return s.stream->meshPart(s.field.threads);
  const FusedField field = s.fuse(failure);
  const MeshSettings m{0, true, s.field.threads, s.field.fillHoles,
                       kCarveMarginVoxels * s.field.voxel};
  MeshStats stats;
  try {
    return internal::meshField(m, s.comm, field, stats);
  } catch (const mpi::Reported&) {
    throw InputError(failure.message());
  }
}

TriangleMesh Fusion::mesh() {
  MeshPart part = meshPart();
  addPartNormals(part, state_->comm);
  return gatherMesh(part, 0, state_->comm);
}

}  // namespace rangefuse
