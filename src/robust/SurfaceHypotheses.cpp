#include "rangefuse/robust/SurfaceHypotheses.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/parallel/Threads.h"
#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse {
namespace {

/// Wheeler's SameSurface test, its distance widened to three deviations of the sample's noise
/// where the sensor is noisier than sameDistance allows for.
bool agrees(const VoxelSums& h, float d, const float f[3], float sigma, const HypothesisParams& p) {
  if (std::abs(h.wd / h.w - d) > std::max(p.sameDistance, 3.0 * sigma)) return false;
  const double dot = h.wf[0] * f[0] + h.wf[1] * f[1] + h.wf[2] * f[2];
  const double norm = std::sqrt(h.wf[0] * h.wf[0] + h.wf[1] * h.wf[1] + h.wf[2] * h.wf[2]);
  return dot >= p.sameCosine * norm;  // f is unit
}

float norm(const float v[3]) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/// The block of `per` T at `block`, made by whichever thread comes first: two threads may reach
/// one brick (its voxels straddle their slabs), and one block wins.
template <class T>
T* blockOf(std::atomic<T*>& block, size_t per, bool create) {
  T* b = block.load();
  if (!b && create) {
    T* mine = new T[per]();
    if (block.compare_exchange_strong(b, mine))
      b = mine;
    else
      delete[] mine;
  }
  return b;
}

}  // namespace

SurfaceHypotheses::SurfaceHypotheses(BrickStore& store, const HypothesisParams& params)
    : store_(store),
      params_(params),
      blocks_(store.brickCount()),
      colourBlocks_(store.hasColour() ? store.brickCount() : 0) {}

SurfaceHypotheses::~SurfaceHypotheses() {
  for (auto& b : blocks_) delete[] b.load();
  for (auto& b : colourBlocks_) delete[] b.load();
}

uint64_t SurfaceHypotheses::extraBytes() const {
  uint64_t n = 0;
  for (const auto& b : blocks_) n += b.load() ? store_.voxelsPerBrick() * sizeof(Extra) : 0;
  for (const auto& b : colourBlocks_)
    n += b.load() ? store_.voxelsPerBrick() * sizeof(ExtraColour) : 0;
  return n;
}

SurfaceHypotheses::Extra* SurfaceHypotheses::extras(size_t at, bool create) {
  const size_t per = store_.voxelsPerBrick();
  Extra* b = blockOf(blocks_[at / per], per, create);
  return b ? b + at % per : nullptr;
}

SurfaceHypotheses::ExtraColour* SurfaceHypotheses::extraColours(size_t at, bool create) {
  const size_t per = store_.voxelsPerBrick();
  if (colourBlocks_.empty()) return nullptr;
  ExtraColour* b = blockOf(colourBlocks_[at / per], per, create);
  return b ? b + at % per : nullptr;
}

void SurfaceHypotheses::add(size_t at, float d, float w, const float f[3], float sigma,
                            const Colour* colour) {
  if (!(w > 0)) return;
  if (colourBlocks_.empty()) colour = nullptr;
  VoxelSums& first = store_.sums()[at];
  // Each colour mean takes the weight its hypothesis held before this sample.
  if (first.images == 0 || agrees(first, d, f, sigma, params_)) {
    if (colour) store_.colours()[at].add(*colour, w, first.w);
    first.add(d, w, f);
    return;
  }
  Extra& extra = *extras(at, true);
  ExtraColour* colours = colour ? extraColours(at, true) : nullptr;
  VoxelSums* lightest = &first;
  VoxelColour* lightestColour = colour ? &store_.colours()[at] : nullptr;
  for (size_t k = 0; k < extra.size(); ++k) {
    VoxelSums& h = extra[k];
    if (h.images == 0 || agrees(h, d, f, sigma, params_)) {
      if (colour) (*colours)[k].add(*colour, w, h.w);
      h.add(d, w, f);
      return;
    }
    if (h.w < lightest->w) lightest = &h, lightestColour = colour ? &(*colours)[k] : nullptr;
  }
  if (w > lightest->w) {
    *lightest = VoxelSums{};
    lightest->add(d, w, f);
    if (colour) *lightestColour = VoxelColour{}, lightestColour->add(*colour, w, 0);
  }
}

int SurfaceHypotheses::lookedThrough(const VoxelSums& h, const Eigen::Vector3d& centre,
                                     const std::vector<SightMap>& sights, int enough) const {
  const Eigen::Vector3d f(h.wf[0], h.wf[1], h.wf[2]);
  const Eigen::Vector3d surface = centre - static_cast<double>(h.wd / h.w) * f.normalized();
  int n = 0;
  for (const SightMap& s : sights)
    if (s.lookedThrough(surface, params_.freeMargin) && ++n >= enough) break;
  return n;
}

bool SurfaceHypotheses::stands(const VoxelSums& h, const Eigen::Vector3d& centre,
                               const std::vector<SightMap>& sights) const {
  const bool freeSpace = std::isfinite(params_.freeMargin);
  if (h.images < params_.minViews)  // one view's word: only if no other image saw through it
    return freeSpace && lookedThrough(h, centre, sights, 1) == 0;
  // Agreed on, it stands unless as many images looked through it as saw it: a ghost that a
  // few frames of a long sequence saw (a person passing) and more frames saw past. Past
  // kVoteViews images it stands on agreement alone, so the test's cost stays bounded.
  return !freeSpace || h.images >= kVoteViews ||
         lookedThrough(h, centre, sights, static_cast<int>(h.images)) < h.images;
}

bool SurfaceHypotheses::merge(const VoxelSums* h, const Eigen::Vector3d& centre,
                              const std::vector<SightMap>& sights, VoxelSums& kept, bool* summed,
                              bool& agreed) const {
  bool stands[kSlots] = {};
  int nearest = -1;
  for (int k = 0; k < kSlots && h[k].images > 0; ++k) {
    const bool enough = h[k].images >= params_.minViews;
    stands[k] = this->stands(h[k], centre, sights);
    if (!stands[k]) continue;
    agreed |= enough;
    if (nearest < 0 || std::abs(h[k].wd / h[k].w) < std::abs(h[nearest].wd / h[nearest].w))
      nearest = k;
  }
  if (nearest < 0) return false;
  // What stands is summed in slot order, as the prism field sums it, except a surface facing
  // the other way that lies apart from the nearest (the far side of a wall thicker than
  // sameDistance): it is left to its own voxels, where it is the nearer. Facing the other way
  // on the same sheet (a shell seen from both sides), it is summed like the rest.
  const float* n = h[nearest].wf;
  const float dn = h[nearest].wd / h[nearest].w;
  bool first = true;
  for (int k = 0; k < kSlots && h[k].images > 0; ++k) {
    if (!stands[k]) continue;
    const float facing = h[k].wf[0] * n[0] + h[k].wf[1] * n[1] + h[k].wf[2] * n[2];
    const bool apart = std::abs(dn + h[k].wd / h[k].w) > params_.sameDistance;
    if (k != nearest && facing < -0.5f * norm(h[k].wf) * norm(n) && apart) continue;
    summed[k] = true;
    if (first) {
      kept = h[k], first = false;
      continue;
    }
    kept += h[k];
  }
  return true;
}

VoxelColour SurfaceHypotheses::mergedColour(const VoxelColour& own, const ExtraColour* extra,
                                            const bool* summed, const VoxelSums* h) {
  if (!extra) return own;  // one hypothesis only: its colour as it is
  Colour sum = Colour::Zero();
  float weight = 0;
  for (int k = 0; k < kSlots; ++k) {
    if (!summed[k]) continue;
    sum += h[k].w * (k == 0 ? own : (*extra)[k - 1]).value();
    weight += h[k].w;
  }
  VoxelColour out;
  out.add(sum / weight, 1, 0);
  return out;
}

HypothesisStats SurfaceHypotheses::resolveBrick(size_t b, const std::vector<SightMap>& sights) {
  HypothesisStats stats;
  const VoxelGrid& grid = store_.grid();
  const int B = grid.brick;
  const size_t perBrick = store_.voxelsPerBrick();
  const BrickCoord brick = mortonDecode(store_.code(b));
  for (size_t l = 0; l < perBrick; ++l) {
    const size_t at = b * perBrick + l;
    VoxelSums& first = store_.sums()[at];
    if (first.images == 0) continue;
    VoxelSums h[kSlots] = {first};
    if (const Extra* e = extras(at, false)) std::copy(e->begin(), e->end(), h + 1);
    const VoxelIndex v =
        brick * B + VoxelIndex(static_cast<int>(l % B), static_cast<int>(l / B % B),
                               static_cast<int>(l / B / B));
    VoxelSums kept;
    bool agreed = false, summed[kSlots] = {};
    if (!merge(h, grid.centre(v), sights, kept, summed, agreed)) {
      ++stats.removed;
      first = VoxelSums{};
      if (store_.hasColour()) store_.colours()[at] = VoxelColour{};
      continue;
    }
    ++(agreed ? stats.agreed : stats.unopposed);
    if (store_.hasColour())
      store_.colours()[at] = mergedColour(store_.colours()[at], extraColours(at, false), summed, h);
    first = kept;
  }
  return stats;
}

HypothesisStats SurfaceHypotheses::resolve(const std::vector<SightMap>& sights, int threads) {
  const size_t bricks = store_.brickCount();
  const size_t parts = std::min<size_t>(bricks, 16 * std::max(1, threads));
  std::vector<HypothesisStats> part(parts);
  parallelFor(parts, threads, [&](size_t k) {
    for (size_t b = bricks * k / parts; b < bricks * (k + 1) / parts; ++b) {
      const HypothesisStats s = resolveBrick(b, sights);
      part[k].agreed += s.agreed, part[k].unopposed += s.unopposed, part[k].removed += s.removed;
    }
  });
  HypothesisStats stats;
  for (const auto& s : part)
    stats.agreed += s.agreed, stats.unopposed += s.unopposed, stats.removed += s.removed;
  return stats;
}

}  // namespace rangefuse
