// rangefuse as a library: range grids and depth images handed over in memory, fused on the
// ranks of an MPI communicator into the mesh the `rangefuse fuse` command would make of the
// same scans. One header; docs/api.md has an example.
#pragma once

#include <mpi.h>

#include <cmath>
#include <memory>
#include <string>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Image.h"
#include "rangefuse/core/MeshPart.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/core/TriangleMesh.h"
#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/io/ScanSourceOptions.h"
#include "rangefuse/options/FieldSettings.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// The library's version, "MAJOR.MINOR.PATCH".
const char* libraryVersion();

/// How frames are prepared before they reach the field, as the command prepares its scans by
/// default (--merge-cells 1, --smooth-noise 1): grid cells merged up to a voxel, depth images'
/// depths noisier than a voxel smoothed, sight maps kept when the method or hole filling needs
/// them.
SurfaceOptions defaultSurface(const FieldSettings& field);

/// What became of a tracked frame.
struct TrackedFrame {
  Pose cameraToWorld;  ///< where it was taken (OpenCV axes); a lost frame keeps the last good one
  bool fused = false;  ///< fitted and fused; false: lost, and left out of the field
  double inliers = 0;  ///< share of its control points that found the field
  double rms = 0;      ///< RMS residual of its last fit, world units
  std::string why;     ///< why it was lost (empty when fused)
};

/// One fusion. Every call is collective over the communicator: each rank makes the same calls
/// with the same frames, in the same order, and the ranks share the work of preparing them
/// and of the field. Errors throw std::runtime_error (InputError for bad input) on every rank,
/// with the message the command prints.
class Fusion {
 public:
  /// `field.voxel` must be positive; `field.threads` 0 shares the node's CPUs among its ranks.
  /// With MPI_COMM_NULL the fusion runs in this process alone (MPI is started if no one has:
  /// no mpirun needed).
  explicit Fusion(const FieldSettings& field, MPI_Comm comm = MPI_COMM_NULL);
  /// As above, with frames prepared by `surface` instead of defaultSurface(field).
  Fusion(const FieldSettings& field, const SurfaceOptions& surface, MPI_Comm comm = MPI_COMM_NULL);
  ~Fusion();
  Fusion(Fusion&&) noexcept;
  Fusion& operator=(Fusion&&) noexcept;

  /// Adds a range grid in its sensor's frame (a pinhole camera or a station at the origin,
  /// else a sensor looking along -z) placed by `pose` (scan to world). `name` heads the
  /// messages about it (default "frame_N"). A grid is never smoothed; add a depth camera's
  /// frames with addDepth.
  void addGrid(RangeGrid grid, const Pose& pose, const std::string& name = "");

  /// Adds a depth image (counts of camera.unit, 0 where nothing was measured) taken by
  /// `camera` at `cameraToWorld` (OpenCV axes: x right, y down, z forward), with an optional
  /// RGB image registered to it (the same size). The images are kept as they are and made a
  /// grid when the field is built, each by the rank whose share it is, in parallel.
  void addDepth(io::DepthImage depth, const io::DepthCamera& camera, const Pose& cameraToWorld,
                const Image* colour = nullptr, const std::string& name = "");

  /// Collective: adds every scan `path` lists, as `rangefuse fuse --scans` reads it (a .conf of
  /// range grids, PTX or E57 stations or depth images; a PTX file; a TUM or Redwood depth
  /// folder with its trajectory), read as `source` says. Only the list is read now; each scan
  /// is read when the field is built, by the rank whose share it is, so ranks do not read
  /// each other's files. A depth folder without a trajectory is refused: track its frames.
  void addScans(const std::string& path, const io::ScanSourceOptions& source = {});

  /// Adds a depth image whose pose is not known: tracked against the field of the frames
  /// tracked before it (the first fixes the world frame: its camera at the origin, OpenCV
  /// axes) and fused into it when the fit holds, as `rangefuse fuse` tracks a depth folder
  /// without a trajectory. A frame that does not fit is reported and left out; after 30 in a
  /// row the stream is given up (an error, and this fusion tracks no more). A fusion either
  /// tracks its frames or is given their poses (addGrid, addDepth), not both.
  /// `time` (seconds; NaN: the frame's index / 30) scales the motion predicted from the frames
  /// before.
  TrackedFrame track(io::DepthImage depth, const io::DepthCamera& camera,
                     const Image* colour = nullptr, double time = NAN,
                     const std::string& name = "");

  /// Frames (and scans) added or tracked so far.
  size_t frames() const;

  /// Collective: fuses every frame added and extracts the mesh; this rank's part of it, as
  /// MeshPart describes (concatenated in rank order they are the whole mesh). Tracked frames:
  /// the tracking field's mesh (prism), or the frames not lost fused again at their tracked
  /// poses by the method asked for.
  MeshPart meshPart();

  /// Collective: fuses every frame added (for tracked frames, takes the tracking field) and
  /// writes the field to an HDF5 checkpoint at `path` (stage "field": docs/checkpoints.md),
  /// atomically, with the frames' names, content hashes and poses, and the settings. `rangefuse
  /// mesh` and `rangefuse info` read it, and Fusion::resume.
  void saveCheckpoint(const std::string& path);

  /// Collective: a fusion holding the finished field of a checkpoint (written by
  /// saveCheckpoint or by `rangefuse fuse --checkpoint`), on `comm`'s ranks however many wrote
  /// it. Its mesh() is that field's; it takes no more frames.
  static Fusion resume(const std::string& path, MPI_Comm comm = MPI_COMM_NULL);

  /// Collective: the whole mesh, with vertex normals, on rank 0 (empty on the others): the
  /// vertices and faces the command writes for the same scans.
  TriangleMesh mesh();

 private:
  struct State;
  explicit Fusion(std::unique_ptr<State> state);
  void refuseResumed(const std::string& name) const;
  std::unique_ptr<State> state_;
};

}  // namespace rangefuse
