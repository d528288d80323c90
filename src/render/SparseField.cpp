#include "rangefuse/render/SparseField.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {

namespace {

void packBrick(std::vector<char>& buf, const BrickStore& store, size_t b) {
  const uint64_t code = store.code(b);
  const size_t per = store.voxelsPerBrick();
  mpi::pack(buf, &code, 1);
  mpi::pack(buf, store.sums().data() + b * per, per);
  if (store.hasColour()) mpi::pack(buf, store.colours().data() + b * per, per);
}

void unpackBricks(const std::vector<char>& buf, size_t per, bool coloured, SparseField& field) {
  for (size_t pos = 0; pos < buf.size();) {
    uint64_t code;
    mpi::unpack(buf, pos, &code, 1);
    std::vector<VoxelSums> sums(per);
    mpi::unpack(buf, pos, sums.data(), per);
    std::vector<VoxelColour> colours(coloured ? per : 0);
    if (coloured) mpi::unpack(buf, pos, colours.data(), per);
    field.addBrick(code, std::move(sums), std::move(colours));
  }
}

/// Brick b of the store as addBrick takes it: its sums and colours (if any).
void addOwnBrick(const BrickStore& store, size_t b, SparseField& field) {
  const size_t per = store.voxelsPerBrick();
  std::vector<VoxelColour> colours;
  if (store.hasColour())
    colours.assign(store.colours().begin() + b * per, store.colours().begin() + (b + 1) * per);
  field.addBrick(
      store.code(b),
      std::vector<VoxelSums>(store.sums().begin() + b * per, store.sums().begin() + (b + 1) * per),
      std::move(colours));
}

}  // namespace

Eigen::AlignedBox3d brickBounds(const VoxelGrid& grid, const std::vector<uint64_t>& codes) {
  Eigen::AlignedBox3d box;
  const int B = grid.brick;
  for (const uint64_t code : codes) {
    const VoxelIndex lo = mortonDecode(code) * B;
    box.extend(grid.centre(lo));
    box.extend(grid.centre(lo + VoxelIndex::Constant(B - 1)));
  }
  return box;
}

namespace {

/// Collective: the box of every rank's bricks.
Eigen::AlignedBox3d allBrickBounds(const BrickStore& store, MPI_Comm comm) {
  std::vector<uint64_t> codes(store.brickCount());
  for (size_t b = 0; b < codes.size(); ++b) codes[b] = store.code(b);
  return mpi::unitedBox(brickBounds(store.grid(), codes), comm);
}

}  // namespace

SparseField SparseField::gather(const BrickStore& store, float minWeight, int root, MPI_Comm comm,
                                const std::function<bool(const BrickCoord&)>& keep) {
  std::vector<char> buf;
  for (size_t b = 0; b < store.brickCount(); ++b)
    if (!keep || keep(mortonDecode(store.code(b)))) packBrick(buf, store, b);
  SparseField field(store.grid(), minWeight);
  unpackBricks(mpi::gatherBytes(buf, root, comm), store.voxelsPerBrick(), store.hasColour(), field);
  field.frame_ = allBrickBounds(store, comm);
  return field;
}

SparseField SparseField::withNeighbours(const BrickStore& store, float minWeight, MPI_Comm comm) {
  const BrickLayout& layout = store.layout();
  const int me = mpi::rank(comm);
  std::vector<std::vector<char>> out(mpi::size(comm));
  SparseField field(store.grid(), minWeight);
  for (size_t b = 0; b < store.brickCount(); ++b) {
    addOwnBrick(store, b, field);
    const BrickCoord c = mortonDecode(store.code(b));
    std::vector<int> sent;
    for (int o = 0; o < 27; ++o) {
      const BrickCoord n = c + BrickCoord(o % 3 - 1, (o / 3) % 3 - 1, o / 9 - 1);
      if ((n.array() < 0).any()) continue;
      const int r = layout.neighbourOwner(mortonEncode(n), me);
      if (r < 0 || r == me) continue;
      if (std::find(sent.begin(), sent.end(), r) != sent.end()) continue;
      sent.push_back(r);
      packBrick(out[r], store, b);
    }
  }
  for (const auto& buf : mpi::exchangeBytes(std::move(out), comm))
    unpackBricks(buf, store.voxelsPerBrick(), store.hasColour(), field);
  field.frame_ = allBrickBounds(store, comm);
  return field;
}

void SparseField::addBrick(uint64_t code, std::vector<VoxelSums> sums,
                           std::vector<VoxelColour> colours) {
  bricks_[code] = std::move(sums);
  if (!colours.empty()) colours_[code] = std::move(colours);
}

std::optional<Colour> SparseField::colour(const Eigen::Vector3d& p) const {
  const VoxelIndex v = grid_.nearest(p);
  if (colours_.empty() || !voxel(v)) return std::nullopt;
  const int B = grid_.brick;
  const auto it = colours_.find(mortonEncode(brickOf(v, B)));
  if (it == colours_.end()) return std::nullopt;
  const VoxelIndex l = v - brickOf(v, B) * B;
  return it->second[(size_t(l.z()) * B + l.y()) * B + l.x()].value();
}

Eigen::AlignedBox3d SparseField::bounds() const {
  if (!frame_.isEmpty()) return frame_;
  std::vector<uint64_t> codes;
  for (const auto& kv : bricks_) codes.push_back(kv.first);
  return brickBounds(grid_, codes);
}

void SparseField::forEachVoxel(
    const std::function<void(const Eigen::Vector3d&, const VoxelSums&)>& f) const {
  const int B = grid_.brick;
  for (const auto& [code, sums] : bricks_) {
    const VoxelIndex lo = mortonDecode(code) * B;
    for (size_t i = 0; i < sums.size(); ++i)
      if (sums[i].w > minWeight_)
        f(grid_.centre(lo + VoxelIndex(int(i % B), int(i / B % B), int(i / B / B))), sums[i]);
  }
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
