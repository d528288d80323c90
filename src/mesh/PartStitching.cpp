#include "rangefuse/mesh/PartStitching.h"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

using Parts = std::vector<std::vector<char>>;

void decodeEdge(uint64_t key, VoxelIndex& v, int& axis) {
  const uint64_t mask = (uint64_t{1} << 20) - 1;
  axis = static_cast<int>(key & 3);
  v = VoxelIndex(static_cast<int>((key >> 2) & mask), static_cast<int>((key >> 22) & mask),
                 static_cast<int>(key >> 42));
}

/// Ranks other than `me` owning one of the four cubes around lattice edge `key`: the only
/// ranks that can also have a vertex on it.
std::vector<int> otherUsers(uint64_t key, const BrickLayout& layout, int me) {
  VoxelIndex v;
  int axis;
  decodeEdge(key, v, axis);
  const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3, B = layout.grid.brick;
  std::vector<int> ranks;
  // Inside a brick all four cubes are in the brick that made the vertex: this rank's.
  if (floorDiv(v[a1], B) == floorDiv(v[a1] - 1, B) && floorDiv(v[a2], B) == floorDiv(v[a2] - 1, B))
    return ranks;
  for (int i = 0; i < 4; ++i) {
    VoxelIndex c = v;
    c[a1] -= i & 1;
    c[a2] -= i >> 1;
    if ((c.array() < 0).any()) continue;
    const int r = layout.neighbourOwner(mortonEncode(brickOf(c, B)), me);
    if (r >= 0 && r != me && std::find(ranks.begin(), ranks.end(), r) == ranks.end())
      ranks.push_back(r);
  }
  return ranks;
}

/// For each local vertex, the other ranks that have it too.
std::vector<std::vector<int>> sharingRanks(const MeshPiece& piece, const BrickLayout& layout,
                                           MPI_Comm comm) {
  const int me = mpi::rank(comm);
  Parts out(mpi::size(comm));
  for (const uint64_t key : piece.keys)
    for (const int r : otherUsers(key, layout, me)) mpi::pack(out[r], &key, 1);
  std::vector<std::vector<int>> users(piece.keys.size());
  const Parts in = mpi::exchangeBytes(std::move(out), comm);
  for (int q = 0; q < static_cast<int>(in.size()); ++q)
    for (size_t pos = 0; pos < in[q].size();) {
      uint64_t key;
      mpi::unpack(in[q], pos, &key, 1);
      const int32_t at = piece.index.find(key);
      if (at >= 0) users[at].push_back(q);
    }
  return users;
}

/// First index of this rank's share and the total, over all ranks.
void scanCounts(uint64_t mine, MPI_Comm comm, uint64_t& first, uint64_t& total) {
  first = 0;
  MPI_Exscan(&mine, &first, 1, MPI_UINT64_T, MPI_SUM, comm);
  if (mpi::rank(comm) == 0) first = 0;  // MPI leaves rank 0's result undefined
  MPI_Allreduce(&mine, &total, 1, MPI_UINT64_T, MPI_SUM, comm);
}

/// Owners tell the other users of each shared vertex its global number.
void shareNumbers(const MeshPiece& piece, const std::vector<std::vector<int>>& users,
                  MeshPart& part, MPI_Comm comm) {
  Parts out(mpi::size(comm));
  for (size_t i = 0; i < users.size(); ++i)
    if (part.owns(i))
      for (const int q : users[i]) {
        mpi::pack(out[q], &piece.keys[i], 1);
        mpi::pack(out[q], &part.global[i], 1);
      }
  for (const auto& buf : mpi::exchangeBytes(std::move(out), comm))
    for (size_t pos = 0; pos < buf.size();) {
      uint64_t key;
      int64_t g;
      mpi::unpack(buf, pos, &key, 1);
      mpi::unpack(buf, pos, &g, 1);
      part.global[piece.index.at(key)] = g;
    }
  if (std::find(part.global.begin(), part.global.end(), -1) != part.global.end())
    throw std::logic_error("mesh stitching: a shared vertex got no number from its owner");
}

}  // namespace

MeshPart stitchPiece(const MeshPiece& piece, const BrickLayout& layout, MPI_Comm comm) {
  MeshPart part;
  part.rank = mpi::rank(comm);
  part.mesh.vertices = piece.positions;
  part.mesh.colours = piece.colours;
  part.mesh.filled = piece.filled;
  part.mesh.faces = piece.faces;
  const std::vector<std::vector<int>> users = sharingRanks(piece, layout, comm);
  part.owner.resize(users.size());
  for (size_t i = 0; i < users.size(); ++i) {
    part.owner[i] = part.rank;
    for (const int q : users[i]) part.owner[i] = std::min(part.owner[i], q);
    part.ownedVertices += part.owns(i);
  }
  scanCounts(part.ownedVertices, comm, part.firstVertex, part.totalVertices);
  scanCounts(part.mesh.faces.size(), comm, part.firstFace, part.totalFaces);
  part.global.assign(users.size(), -1);
  int64_t next = static_cast<int64_t>(part.firstVertex);
  for (size_t i = 0; i < users.size(); ++i)
    if (part.owns(i)) part.global[i] = next++;
  shareNumbers(piece, users, part, comm);
  return part;
}

void addPartNormals(MeshPart& part, MPI_Comm comm) {
  std::vector<Eigen::Vector3d>& n = part.mesh.normals;
  n.assign(part.mesh.vertices.size(), Eigen::Vector3d::Zero());
  // Face normals of vertices owned elsewhere, kept one by one so that the owner adds them in
  // global face order: a sum of partial sums would round differently.
  std::map<int32_t, std::vector<Eigen::Vector3d>> foreign;
  for (const Triangle& t : part.mesh.faces) {
    const auto& v = part.mesh.vertices;
    const Eigen::Vector3d fn = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]);
    for (int k = 0; k < 3; ++k) {
      if (part.owns(t[k]))
        n[t[k]] += fn;
      else
        foreign[t[k]].push_back(fn);
    }
  }
  Parts out(mpi::size(comm));
  for (const auto& [i, list] : foreign) {
    const uint64_t count = list.size();
    mpi::pack(out[part.owner[i]], &part.global[i], 1);
    mpi::pack(out[part.owner[i]], &count, 1);
    mpi::pack(out[part.owner[i]], list.data(), count);
  }
  std::vector<int32_t> localOf(part.ownedVertices);
  for (size_t i = 0; i < part.global.size(); ++i)
    if (part.owns(i)) localOf[part.global[i] - part.firstVertex] = static_cast<int32_t>(i);
  // Only higher ranks send (the owner is the lowest user), and in rank order: face order.
  for (const auto& buf : mpi::exchangeBytes(std::move(out), comm))
    for (size_t pos = 0; pos < buf.size();) {
      int64_t g;
      uint64_t count;
      mpi::unpack(buf, pos, &g, 1);
      mpi::unpack(buf, pos, &count, 1);
      Eigen::Vector3d& sum = n[localOf[g - part.firstVertex]];
      for (uint64_t k = 0; k < count; ++k) {
        Eigen::Vector3d fn;
        mpi::unpack(buf, pos, &fn, 1);
        sum += fn;
      }
    }
  for (size_t i = 0; i < n.size(); ++i)
    if (part.owns(i) && n[i].norm() > 0) n[i].normalize();
}

TriangleMesh gatherMesh(const MeshPart& part, int root, MPI_Comm comm) {
  std::vector<char> mine;
  const bool normals = !part.mesh.normals.empty();
  const bool colours = part.colour != ColourKind::none;
  const bool filled = part.marksFilled;
  const uint64_t nf = part.mesh.faces.size();
  mpi::pack(mine, &part.ownedVertices, 1);
  for (size_t i = 0; i < part.global.size(); ++i)
    if (part.owns(i)) {
      mpi::pack(mine, &part.mesh.vertices[i], 1);
      if (normals) mpi::pack(mine, &part.mesh.normals[i], 1);
      if (colours) mpi::pack(mine, &part.mesh.colours[i], 1);
      if (filled) mpi::pack(mine, &part.mesh.filled[i], 1);
    }
  mpi::pack(mine, &nf, 1);
  for (const Triangle& t : part.mesh.faces) {
    const Triangle g = {static_cast<int32_t>(part.global[t[0]]),
                        static_cast<int32_t>(part.global[t[1]]),
                        static_cast<int32_t>(part.global[t[2]])};
    mpi::pack(mine, &g, 1);
  }
  const std::vector<char> all = mpi::gatherBytes(mine, root, comm);
  TriangleMesh mesh;
  for (size_t pos = 0; pos < all.size();) {
    uint64_t count;
    mpi::unpack(all, pos, &count, 1);
    for (uint64_t k = 0; k < count; ++k) {
      mpi::unpack(all, pos, &mesh.vertices.emplace_back(), 1);
      if (normals) mpi::unpack(all, pos, &mesh.normals.emplace_back(), 1);
      if (colours) mpi::unpack(all, pos, &mesh.colours.emplace_back(), 1);
      if (filled) mpi::unpack(all, pos, &mesh.filled.emplace_back(), 1);
    }
    mpi::unpack(all, pos, &count, 1);
    for (uint64_t k = 0; k < count; ++k) mpi::unpack(all, pos, &mesh.faces.emplace_back(), 1);
  }
  return mesh;
}

}  // namespace rangefuse
