#include "rangefuse/mesh/DistributedMesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "HoleFilling.h"
#include "rangefuse/mesh/MarchingCubes.h"
#include "rangefuse/mesh/PartStitching.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"

namespace rangefuse {
namespace {

template <class T>
using BrickMap = std::map<uint64_t, std::vector<T>>;
using BrickValues = BrickMap<float>;
using BrickColours = BrickMap<Eigen::Vector3f>;
using BrickFlags = BrickMap<uint8_t>;

/// Offsets of the bricks whose first layer a brick's cubes read.
const BrickCoord kUpper[7] = {{1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1},
                              {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};

/// Ranks other than this one that own a brick reading local brick b as its upper neighbour.
std::set<int> haloReaders(const BrickLayout& layout, uint64_t code, int me) {
  std::set<int> readers;
  const BrickCoord c = mortonDecode(code);
  for (const BrickCoord& o : kUpper) {
    const BrickCoord y = c - o;
    if ((y.array() < 0).any()) continue;
    const int owner = layout.neighbourOwner(mortonEncode(y), me);
    if (owner >= 0 && owner != me) readers.insert(owner);
  }
  return readers;
}

/// The values of other ranks' bricks that this rank's cubes read.
template <class T>
BrickMap<T> exchangeHalo(const BrickLayout& layout, size_t per, const BrickMap<T>& local,
                         MPI_Comm comm) {
  const int n = mpi::size(comm), me = mpi::rank(comm);
  std::vector<std::vector<char>> out(n);
  for (const auto& [code, values] : local)
    for (int r : haloReaders(layout, code, me)) {
      mpi::pack(out[r], &code, 1);
      mpi::pack(out[r], values.data(), values.size());
    }
  BrickMap<T> halo;
  for (const auto& buf : mpi::exchangeBytes(std::move(out), comm))
    for (size_t pos = 0; pos < buf.size();) {
      uint64_t code;
      mpi::unpack(buf, pos, &code, 1);
      std::vector<T>& v = halo[code];
      v.resize(per);
      mpi::unpack(buf, pos, v.data(), per);
    }
  return halo;
}

/// The (B+1)^3 values a brick's cubes need: its own and the first layer of its upper
/// neighbours; `missing` where no brick exists.
template <class T>
std::vector<T> blockValues(uint64_t code, int B, const BrickMap<T>& local, const BrickMap<T>& halo,
                           const T& missing) {
  std::vector<T> values(static_cast<size_t>(B + 1) * (B + 1) * (B + 1), missing);
  const BrickCoord c = mortonDecode(code);
  const std::vector<T>* src[8] = {};
  for (int o = 0; o < 8; ++o) {
    const uint64_t nc = mortonEncode(c + BrickCoord(o & 1, (o >> 1) & 1, o >> 2));
    auto it = local.find(nc);
    if (it != local.end())
      src[o] = &it->second;
    else if ((it = halo.find(nc)) != halo.end())
      src[o] = &it->second;
  }
  size_t i = 0;
  for (int z = 0; z <= B; ++z)
    for (int y = 0; y <= B; ++y)
      for (int x = 0; x <= B; ++x, ++i) {
        const int o = (x / B) | (y / B) << 1 | (z / B) << 2;
        if (src[o]) values[i] = (*src[o])[(static_cast<size_t>(z % B) * B + y % B) * B + x % B];
      }
  return values;
}

/// What a rank's cubes read: its bricks' values (and colours, and carved flags, when the field
/// has them) and the halo of other ranks' bricks.
struct BlockSources {
  BrickValues local, halo;
  BrickColours localColours, haloColours;
  BrickFlags localFilled, haloFilled;  ///< stored bricks' carved flags (others: all carved)
  bool coloured = false, carved = false;
  float outside = NAN;  ///< the value of voxels in no brick: NaN, or empty space when carved
};

/// A brick's block: its distances and, when the field has them, its colours and carved flags.
FieldBlock blockFor(uint64_t code, int B, const BlockSources& s) {
  FieldBlock block;
  block.base = mortonDecode(code) * B;
  block.cells = B;
  block.values = blockValues(code, B, s.local, s.halo, s.outside);
  if (s.coloured)
    block.colours = blockValues(code, B, s.localColours, s.haloColours,
                                Eigen::Vector3f(Eigen::Vector3f::Zero()));
  if (s.carved) block.filled = blockValues(code, B, s.localFilled, s.haloFilled, uint8_t{1});
  return block;
}

/// Brick b's voxel colours.
std::vector<Eigen::Vector3f> brickColours(const BrickStore& store, size_t b) {
  const size_t per = store.voxelsPerBrick();
  std::vector<Eigen::Vector3f> c(per);
  const VoxelColour* s = store.colours().data() + b * per;
  for (size_t i = 0; i < per; ++i) c[i] = s[i].value();
  return c;
}

/// Collective: the faces with a filled vertex and their area, over all ranks.
void countFilled(MeshPart& part, MPI_Comm comm) {
  const TriangleMesh& m = part.mesh;
  double area = 0;
  uint64_t faces = 0;
  for (const Triangle& t : m.faces) {
    if (!m.filled[t[0]] && !m.filled[t[1]] && !m.filled[t[2]]) continue;
    ++faces;
    area += 0.5 *
            (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  }
  MPI_Allreduce(&faces, &part.filledFaces, 1, MPI_UINT64_T, MPI_SUM, comm);
  MPI_Allreduce(&area, &part.filledArea, 1, MPI_DOUBLE, MPI_SUM, comm);
}

}  // namespace

std::vector<float> brickDistances(const BrickStore& store, size_t b, float minWeight) {
  const size_t per = store.voxelsPerBrick();
  std::vector<float> d(per);
  const VoxelSums* s = store.sums().data() + b * per;
  for (size_t i = 0; i < per; ++i) d[i] = s[i].w > minWeight ? s[i].wd / s[i].w : NAN;
  return d;
}

MeshPart extractDistributedMesh(const BrickStore& store, float minWeight, MPI_Comm comm,
                                MeshStats* stats, int threads, const HoleFill* fill) {
  const size_t n = store.brickCount();
  const size_t parts = std::max<size_t>(1, std::min<size_t>(std::max(1, threads), n));
  std::vector<std::vector<float>> distances(n);
  std::vector<std::vector<uint8_t>> carved(fill ? n : 0);
  parallelFor(parts, threads, [&](size_t k) {
    for (size_t b = n * k / parts; b < n * (k + 1) / parts; ++b) {
      distances[b] = brickDistances(store, b, minWeight);
      if (fill) carved[b] = internal::carveBrick(store.code(b), store.grid(), *fill, distances[b]);
    }
  });
  BlockSources s;
  for (size_t b = 0; b < n; ++b) s.local[store.code(b)] = std::move(distances[b]);
  const BrickLayout* layout = &store.layout();
  BrickLayout filledLayout;
  if (fill) {
    BrickCoord lo, hi;
    internal::fillRegion(store.layout(), comm, lo, hi);
    BrickValues more =
        internal::fillBricks(store.layout(), lo, hi, *fill, mpi::rank(comm), threads);
    filledLayout = internal::withFillBricks(store.layout(), more);
    layout = &filledLayout;
    // Flags for the stored bricks only: a fill brick, like a voxel in no brick, is all carved.
    for (size_t b = 0; b < n; ++b) s.localFilled[store.code(b)] = std::move(carved[b]);
    s.local.merge(more);
    s.carved = true;
    s.outside = fill->value;
  }
  const size_t per = store.voxelsPerBrick();
  s.halo = exchangeHalo(*layout, per, s.local, comm);
  if (s.carved) s.haloFilled = exchangeHalo(*layout, per, s.localFilled, comm);
  s.coloured = store.hasColour();
  if (s.coloured) {  // fill bricks carry no colour: they read as black, like unobserved voxels
    for (size_t b = 0; b < n; ++b) s.localColours[store.code(b)] = brickColours(store, b);
    s.haloColours = exchangeHalo(*layout, per, s.localColours, comm);
  }
  // Runs of bricks in code order, one piece each, joined as if one piece had taken every cube.
  std::vector<uint64_t> codes;
  for (const auto& entry : s.local) codes.push_back(entry.first);
  const size_t m = codes.size();
  const size_t runs = std::max<size_t>(1, std::min<size_t>(std::max(1, threads), m));
  std::vector<MeshPiece> pieces(runs);
  parallelFor(runs, threads, [&](size_t k) {
    for (size_t b = m * k / runs; b < m * (k + 1) / runs; ++b)
      extractBlock(blockFor(codes[b], store.grid().brick, s), store.grid(), pieces[k]);
  });
  MeshPiece piece = joinPieces(std::move(pieces));
  if (stats) {
    stats->haloBricksReceived = s.halo.size();
    stats->localTriangles = piece.faces.size();
  }
  MeshPart part = stitchPiece(piece, *layout, comm);
  part.colour = store.colourKind();
  part.marksFilled = s.carved;
  if (s.carved) countFilled(part, comm);
  return part;
}

}  // namespace rangefuse
