#include "rangefuse/render/SparseField.h"

#include <cmath>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {

SparseField SparseField::gather(const BrickStore& store, float minWeight, int root, MPI_Comm comm) {
  std::vector<char> buf;
  const size_t per = store.voxelsPerBrick();
  for (size_t b = 0; b < store.brickCount(); ++b) {
    const uint64_t code = store.code(b);
    mpi::pack(buf, &code, 1);
    mpi::pack(buf, store.sums().data() + b * per, per);
  }
  const std::vector<char> all = mpi::gatherBytes(buf, root, comm);
  SparseField field(store.grid(), minWeight);
  for (size_t pos = 0; pos < all.size();) {
    uint64_t code;
    mpi::unpack(all, pos, &code, 1);
    std::vector<VoxelSums> sums(per);
    mpi::unpack(all, pos, sums.data(), per);
    field.addBrick(code, std::move(sums));
  }
  return field;
}

void SparseField::addBrick(uint64_t code, std::vector<VoxelSums> sums) {
  bricks_[code] = std::move(sums);
}

Eigen::AlignedBox3d SparseField::bounds() const {
  Eigen::AlignedBox3d box;
  const int B = grid_.brick;
  for (const auto& kv : bricks_) {
    const VoxelIndex lo = mortonDecode(kv.first) * B;
    box.extend(grid_.centre(lo));
    box.extend(grid_.centre(lo + VoxelIndex::Constant(B - 1)));
  }
  return box;
}

const VoxelSums* SparseField::voxel(const VoxelIndex& v) const {
  if ((v.array() < 0).any()) return nullptr;
  const int B = grid_.brick;
  auto it = bricks_.find(mortonEncode(brickOf(v, B)));
  if (it == bricks_.end()) return nullptr;
  const VoxelIndex l = v - brickOf(v, B) * B;
  const VoxelSums* s = &it->second[(size_t(l.z()) * B + l.y()) * B + l.x()];
  return s->w > minWeight_ ? s : nullptr;
}

bool SparseField::distance(const Eigen::Vector3d& p, double& d) const {
  Eigen::Vector3d c;
  VoxelIndex base;
  for (int a = 0; a < 3; ++a) {
    const double x = grid_.coord(p, a);
    base[a] = static_cast<int>(std::floor(x));
    c[a] = x - base[a];
  }
  d = 0;
  for (int k = 0; k < 8; ++k) {
    const VoxelIndex o(k & 1, (k >> 1) & 1, k >> 2);
    const VoxelSums* s = voxel(base + o);
    if (!s) return false;
    double w = 1;
    for (int a = 0; a < 3; ++a) w *= o[a] ? c[a] : 1 - c[a];
    d += w * s->wd / s->w;
  }
  return true;
}

Eigen::Vector3d SparseField::gradient(const Eigen::Vector3d& p) const {
  const VoxelSums* s = voxel(grid_.nearest(p));
  if (!s) return Eigen::Vector3d::Zero();
  Eigen::Vector3d f(s->wf[0], s->wf[1], s->wf[2]);
  return f.norm() > 0 ? f.normalized() : f;
}

}  // namespace rangefuse
