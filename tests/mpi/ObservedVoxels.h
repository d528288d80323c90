// Every observed voxel of a distributed field, gathered on every rank, and their comparison
// bit for bit: how the growing-field tests hold a fast path to a simple one.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <map>

#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse::test {

using VoxelKey = std::pair<uint64_t, uint32_t>;  // brick code, voxel within the brick
using VoxelValues = std::map<VoxelKey, std::array<float, 6>>;

/// The voxels with a weight or an image of every rank's part of a field over `comm`: wd, w, wf
/// and images by (code, voxel). A voxel held by two ranks fails the test.
inline VoxelValues observedVoxels(const BrickStore& store, MPI_Comm comm) {
  std::vector<char> mine;
  const size_t per = store.voxelsPerBrick();
  for (size_t b = 0; b < store.brickCount(); ++b)
    for (uint32_t k = 0; k < per; ++k) {
      const VoxelSums& s = store.sums()[b * per + k];
      if (s.w == 0 && s.images == 0) continue;
      const uint64_t code = store.code(b);
      const std::array<float, 6> v{s.wd, s.w, s.wf[0], s.wf[1], s.wf[2], s.images};
      mpi::pack(mine, &code, 1);
      mpi::pack(mine, &k, 1);
      mpi::pack(mine, v.data(), v.size());
    }
  VoxelValues all;
  for (const auto& part : mpi::allgatherBytes(mine, comm))
    for (size_t at = 0; at < part.size();) {
      VoxelKey key;
      std::array<float, 6> v;
      mpi::unpack(part, at, &key.first, 1);
      mpi::unpack(part, at, &key.second, 1);
      mpi::unpack(part, at, v.data(), v.size());
      EXPECT_TRUE(all.emplace(key, v).second) << "a voxel held by two ranks";
    }
  return all;
}

/// Same voxels, same bits.
inline void expectIdentical(const VoxelValues& a, const VoxelValues& b) {
  ASSERT_EQ(a.size(), b.size());
  size_t differing = 0;
  for (auto ia = a.begin(), ib = b.begin(); ia != a.end(); ++ia, ++ib)
    differing += ia->first != ib->first ||
                 std::memcmp(ia->second.data(), ib->second.data(), sizeof(float) * 6) != 0;
  EXPECT_EQ(differing, 0u) << "of " << a.size() << " voxels";
}

}  // namespace rangefuse::test
