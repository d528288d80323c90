// The voxel rows a prism may cross, cut to its slabs, and the batched solve along them (private
// to the prism stage): shared by rasterizePrism and the field's integrator.
#pragma once

#include <cstdint>

#include "PrismSolve.h"
#include "rangefuse/prism/Prism.h"
#include "rangefuse/volume/VoxelGrid.h"

namespace rangefuse::internal {

/// The voxel rows a prism may cross: rows run along the longest side of the prism's box, and
/// each is cut to where it lies between five slabs that hold the prism's six corner points
/// (and so the whole prism, a blend of its corners): across its two end triangles and its
/// three sides. Cheap (a few products a row) and never too short, so the exact solve at each
/// voxel left decides, as it does for every voxel of the box.
class PrismRows {
 public:
  PrismRows(const Prism& prism, const VoxelGrid& grid);

  static constexpr int kSlabs = 5;

  bool empty() const { return (lo.array() > hi.array()).any(); }

  /// Each slab's value at the start of the rows with first fixed coordinate vb (the part of
  /// span's sum that a run of rows shares, so it is added once for them all).
  struct Plane {
    double at[kSlabs], flatAt[kSlabs];
  };
  void plane(int vb, Plane& p) const;
  /// Voxels [a0, a1] along `along` of the row at (vb, vc) on the two other axes (p: vb's
  /// plane), false if none.
  bool span(const Plane& p, int vc, int& a0, int& a1) const;

  int along = 0, b = 1, c = 2;  ///< the rows' axis and the two fixed ones
  VoxelIndex lo, hi;            ///< voxels of the prism's box

 private:
  /// The prism lies where lo <= atRow0 + perB vb + perC vc + perStep a <= hi (a: along).
  /// perStep is kept as its inverse (a product is cheaper than a division); a slab whose
  /// inverse is not finite does not vary along a row and goes to flat_.
  struct Slab {
    double lo, hi, atRow0, perB, perC, perStepInv;
  };
  Slab slabs_[kSlabs];  ///< slabs that cut rows
  Slab flat_[kSlabs];   ///< slabs parallel to the rows (perStep 0)
  int count_ = 0, flatCount_ = 0;
};

inline void PrismRows::plane(int vb, Plane& p) const {
  for (int k = 0; k < count_; ++k) p.at[k] = slabs_[k].atRow0 + slabs_[k].perB * vb;
  for (int k = 0; k < flatCount_; ++k) p.flatAt[k] = flat_[k].atRow0 + flat_[k].perB * vb;
}

inline bool PrismRows::span(const Plane& p, int vc, int& a0, int& a1) const {
  double from = lo[along], to = hi[along];
  // Without a branch per slab (rows a prism misses are about two in three, unpredictably):
  // each slab's interval along the row, cut from the others by min and max.
  for (int k = 0; k < count_; ++k) {
    const Slab& s = slabs_[k];
    const double at = p.at[k] + s.perC * vc;
    const double t0 = (s.lo - at) * s.perStepInv, t1 = (s.hi - at) * s.perStepInv;
    from = std::max(from, std::min(t0, t1));
    to = std::min(to, std::max(t0, t1));
  }
  for (int k = 0; k < flatCount_; ++k) {  // slabs the row runs inside of: all of it or none
    const Slab& s = flat_[k];
    const double at = p.flatAt[k] + s.perC * vc;
    if (at < s.lo || at > s.hi) return false;
  }
  if (!(from <= to)) return false;
  const double pad = 1e-6;  // lattice units: rounding never cuts a voxel the solve would keep
  a0 = std::max(lo[along], ceilToInt(from - pad));  // from and to lie within the box
  a1 = std::min(hi[along], floorToInt(to + pad));
  return a0 <= a1;
}

/// Visits the voxels of `rows` (PrismRows of the prism, perhaps with a smaller box) that lie
/// inside the prism: slotOf(VoxelIndex) is asked first, as a voxel joins a batch of feet to
/// solve (a negative answer skips it), then visit(VoxelIndex, slot, PrismFoot) for those inside.
template <class SlotOf, class Visit>
void rasterizeRows(const Prism& prism, const VoxelGrid& grid, const PrismRows& rows,
                   SlotOf&& slotOf, Visit&& visit) {
  if (rows.empty()) return;
  const PrismCubic cubic(prism);
  VoxelIndex voxels[kFootBatch];
  int64_t slots[kFootBatch];
  Eigen::Vector3d centres[kFootBatch];
  PrismFoot feet[kFootBatch];
  bool inside[kFootBatch];
  int n = 0;
  const auto flush = [&] {
    solveFeet(prism, cubic, centres, n, feet, inside);
    for (int i = 0; i < n; ++i)
      if (inside[i]) visit(voxels[i], slots[i], feet[i]);
    n = 0;
  };
  VoxelIndex v;
  int a0, a1;
  PrismRows::Plane plane;
  for (v[rows.b] = rows.lo[rows.b]; v[rows.b] <= rows.hi[rows.b]; ++v[rows.b]) {
    rows.plane(v[rows.b], plane);
    for (v[rows.c] = rows.lo[rows.c]; v[rows.c] <= rows.hi[rows.c]; ++v[rows.c]) {
      if (!rows.span(plane, v[rows.c], a0, a1)) continue;
      for (v[rows.along] = a0; v[rows.along] <= a1; ++v[rows.along]) {
        const int64_t slot = slotOf(v);
        if (slot < 0) continue;
        voxels[n] = v;
        slots[n] = slot;
        centres[n] = grid.centre(v);
        if (++n == kFootBatch) flush();
      }
    }
  }
  if (n > 0) flush();
}

}  // namespace rangefuse::internal
