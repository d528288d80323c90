#include "rangefuse/mesh/DistributedMesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

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
BrickMap<T> exchangeHalo(const BrickStore& store, const BrickMap<T>& local, MPI_Comm comm) {
  const int n = mpi::size(comm), me = mpi::rank(comm);
  std::vector<std::vector<char>> out(n);
  for (const auto& [code, values] : local)
    for (int r : haloReaders(store.layout(), code, me)) {
      mpi::pack(out[r], &code, 1);
      mpi::pack(out[r], values.data(), values.size());
    }
  BrickMap<T> halo;
  const size_t per = store.voxelsPerBrick();
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

/// A brick's block: its distances and, when the field has colour, its colours.
FieldBlock blockFor(uint64_t code, int B, const BrickValues& local, const BrickValues& halo,
                    const BrickColours* localColours, const BrickColours* haloColours) {
  FieldBlock block;
  block.base = mortonDecode(code) * B;
  block.cells = B;
  block.values = blockValues(code, B, local, halo, static_cast<float>(NAN));
  if (localColours)
    block.colours =
        blockValues(code, B, *localColours, *haloColours, Eigen::Vector3f(Eigen::Vector3f::Zero()));
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

}  // namespace

std::vector<float> brickDistances(const BrickStore& store, size_t b, float minWeight) {
  const size_t per = store.voxelsPerBrick();
  std::vector<float> d(per);
  const VoxelSums* s = store.sums().data() + b * per;
  for (size_t i = 0; i < per; ++i) d[i] = s[i].w > minWeight ? s[i].wd / s[i].w : NAN;
  return d;
}

MeshPart extractDistributedMesh(const BrickStore& store, float minWeight, MPI_Comm comm,
                                MeshStats* stats, int threads) {
  const size_t n = store.brickCount();
  const size_t parts = std::max<size_t>(1, std::min<size_t>(std::max(1, threads), n));
  std::vector<std::vector<float>> distances(n);
  parallelFor(parts, threads, [&](size_t k) {
    for (size_t b = n * k / parts; b < n * (k + 1) / parts; ++b)
      distances[b] = brickDistances(store, b, minWeight);
  });
  BrickValues local;
  for (size_t b = 0; b < n; ++b) local[store.code(b)] = std::move(distances[b]);
  const BrickValues halo = exchangeHalo(store, local, comm);
  BrickColours localColours, haloColours;
  if (store.hasColour()) {
    for (size_t b = 0; b < n; ++b) localColours[store.code(b)] = brickColours(store, b);
    haloColours = exchangeHalo(store, localColours, comm);
  }
  const bool coloured = store.hasColour();
  // Runs of bricks in order, one piece each, joined as if one piece had taken every cube.
  std::vector<MeshPiece> pieces(parts);
  parallelFor(parts, threads, [&](size_t k) {
    for (size_t b = n * k / parts; b < n * (k + 1) / parts; ++b)
      extractBlock(blockFor(store.code(b), store.grid().brick, local, halo,
                            coloured ? &localColours : nullptr, coloured ? &haloColours : nullptr),
                   store.grid(), pieces[k]);
  });
  MeshPiece piece = joinPieces(std::move(pieces));
  if (stats) {
    stats->haloBricksReceived = halo.size();
    stats->localTriangles = piece.faces.size();
  }
  MeshPart part = stitchPiece(piece, store.layout(), comm);
  part.colour = store.colourKind();
  return part;
}

}  // namespace rangefuse
