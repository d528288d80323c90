// Control points kept on the ranks that evaluate them: a rank holds only the scans it read, and
// sending every control point to its voxel's owner at every fit costs more than the fit itself.
// Points are routed once with a reach, and again only when their scan has moved past it.
#pragma once

#include <mpi.h>

#include <unordered_map>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/register/ScanSource.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

/// Control points in world coordinates, with their normals and weights, and the scan's sensor
/// (their lines of sight) at the same pose.
struct ControlPoints {
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<double> weights;
  Sensor sensor;
};

/// Every scan's control points (every stride-th vertex with a positive confidence), each kept on
/// the ranks owning its brick or a neighbour of it where it was routed. A point whose scan
/// moved less than a brick edge less one voxel (the reach) since then is therefore on the rank
/// owning its nearest voxel.
class ControlRouting {
 public:
  /// Collective. A rank holds only the scans it read. `lazy`: each scan is looked at when first
  /// routed (a stream's frames are read as they come), not all of them now. `noiseFloor` > 0
  /// weighs each point by its scan's depth noise there (controlWeight).
  ControlRouting(const ScanSource& scans, int stride, MPI_Comm comm, bool lazy = false,
                 double noiseFloor = 0);

  /// Collective: sends scans `which`, placed at `poses`, to the owners of `store`'s bricks. Call
  /// it whenever the store's bricks change.
  void route(const std::vector<size_t>& which, const std::vector<Pose>& poses,
             const BrickStore& store);

  /// Collective: the control points of scan i at `pose` that this rank holds, in scan order;
  /// among them every point whose nearest voxel lies in this rank's bricks. Every rank must
  /// ask for the same scan and pose: when the scan moved past the reach, it is routed again.
  /// `every` > 1 gives a coarser level: the points of every `every`-th control vertex.
  ControlPoints at(size_t i, const Pose& pose, const BrickStore& store, int every = 1);

  /// Collective: the ball, sensor and count of each listed scan not yet known, from its reader
  /// (route() learns the scans it routes).
  void learn(const std::vector<size_t>& which);
  /// Takes in scans that joined the source since (a stream that is still being recorded).
  void follow();

  /// How many control points scan i has, once learnt.
  double count(size_t i) const { return counts_[i]; }

  /// Forgets scan i's routed points (a tracked frame once it is in the field).
  void release(size_t i);

  /// A ball holding every scan's control points at `poses`: centre and radius. The same on
  /// every rank, and it depends on the scans and poses alone (not on any field's bricks).
  Eigen::Vector4d ball(const std::vector<Pose>& poses) const;

  /// How many times a scan moved past the reach and was routed again.
  size_t reroutes() const { return reroutes_; }

 private:
  /// A scan's control points held here, in the scan's frame: the vertex numbers of those
  /// needed here when this rank read the scan and keeps it in memory, copies otherwise.
  struct Held {
    Pose routedAt;
    std::shared_ptr<const PrismScan> scan;  ///< the kept scan `vertices` number into
    std::vector<uint32_t> vertices;
    std::vector<Eigen::Vector3d> points, normals;
    std::vector<double> weights;
    std::vector<uint32_t> pointVertices;  ///< the vertex each copied point came from
  };

  /// Vertex v's weight: its confidence, times (with a noise floor) floor / (floor + sigma),
  /// sigma its depth noise, `quadratic` * depth^2 (RangeNoise::quadratic).
  double weightOf(const PrismScan& scan, size_t v, double quadratic) const;

  /// Appends scan i's control points at `pose` to out[r] for every rank r owning their brick or
  /// a neighbour (owners caches the ranks around each brick); its own go to held_[i].
  void packControlPoints(size_t i, const Pose& pose, const BrickLayout& layout, int me,
                         std::unordered_map<uint64_t, std::vector<int>>& owners,
                         std::vector<std::vector<char>>& out);

  /// Adds the control points other ranks sent (and those this rank sent itself) to held_,
  /// those near a brick of `store`: a sender that does not know the bricks far from its own
  /// sends a point to the owner of its brick's range, which may have no brick there.
  void receive(const std::vector<std::vector<char>>& in, const BrickStore& store);

  /// An upper bound on how far any control point of scan i moves from `from` to `to`.
  double motionBound(size_t i, const Pose& from, const Pose& to) const;

  const ScanSource& scans_;
  int stride_;
  double noiseFloor_;
  MPI_Comm comm_;
  std::vector<Eigen::Vector4d> spheres_;  ///< per scan: centre and radius of its control points
  std::vector<Sensor> sensors_;           ///< per scan, in its frame
  std::vector<double> counts_;            ///< per scan, its control points
  std::vector<char> known_;               ///< per scan: ball, sensor and count learnt
  std::vector<Held> held_;
  size_t reroutes_ = 0;
};

}  // namespace rangefuse
