#include <cmath>
#include <limits>

#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/render/Render.h"

namespace rangefuse {
namespace {

/// For each pixel, the rank whose crossing is nearest (the lowest rank on a tie); every rank
/// gets the answer.
std::vector<int> nearestRanks(const std::vector<PixelHit>& hits, MPI_Comm comm) {
  struct DepthRank {
    double t;
    int rank;
  };
  std::vector<DepthRank> mine(hits.size()), best(hits.size());
  const int me = mpi::rank(comm);
  for (size_t i = 0; i < hits.size(); ++i)
    mine[i] = {std::isnan(hits[i].t) ? std::numeric_limits<double>::infinity() : hits[i].t, me};
  MPI_Allreduce(mine.data(), best.data(), static_cast<int>(hits.size()), MPI_DOUBLE_INT, MPI_MINLOC,
                comm);
  std::vector<int> winner(hits.size(), -1);
  for (size_t i = 0; i < hits.size(); ++i)
    if (std::isfinite(best[i].t)) winner[i] = best[i].rank;
  return winner;
}

}  // namespace

Image renderDistributed(const BrickStore& store, float minWeight, const ViewSettings& view,
                        int root, MPI_Comm comm) {
  const SparseField near = SparseField::withNeighbours(store, minWeight, comm);
  const BrickLayout& layout = store.layout();
  const int me = mpi::rank(comm);
  // A crossing belongs to the rank owning the brick of its later sample: exactly one rank.
  const BrickFilter mine = [&](const BrickCoord& b) {
    const int64_t i = layout.find(mortonEncode(b));
    return i >= 0 && layout.ownerOf(i) == me;
  };
  // The same frame on every rank: the surface each holds, united.
  const Eigen::AlignedBox3d extent =
      view.camera ? Eigen::AlignedBox3d()
                  : mpi::unitedBox(surfaceExtent(near, viewAxes(view)), comm);
  const std::vector<PixelHit> hits = castRays(near, extent, view, mine);
  const std::vector<int> winner = nearestRanks(hits, comm);
  Image img(view.width, view.height, 0);
  for (size_t i = 0; i < hits.size(); ++i)
    for (int k = 0; k < 3; ++k)
      img.rgb[3 * i + k] = winner[i] == me               ? hits[i].rgb[k]
                           : winner[i] < 0 && me == root ? kBackground[k]
                                                         : 0;
  // Each pixel is non-zero on at most one rank, so a sum composites without loss.
  Image out(view.width, view.height, 0);
  MPI_Reduce(img.rgb.data(), out.rgb.data(), static_cast<int>(img.rgb.size()), MPI_UINT8_T, MPI_SUM,
             root, comm);
  return out;
}

}  // namespace rangefuse
