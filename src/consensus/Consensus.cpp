#include "rangefuse/consensus/Consensus.h"

#include <algorithm>

namespace rangefuse {
namespace {

/// Lines 2-5 of ClosestSignedDistance, shared by both methods.
SignedDistance signedFrom(const Eigen::Vector3d& x, const SurfaceObservation& s) {
  SignedDistance out;
  const Eigen::Vector3d r = x - s.point;
  out.d = r.norm();
  if (s.normal.dot(r) < 0) out.d = -out.d;
  // The gradient of the signed field points away from the surface outside, toward it inside.
  out.gradient = out.d != 0 ? Eigen::Vector3d(r / out.d) : s.normal;
  out.weight = s.confidence;
  out.views = s.views;
  return out;
}

/// x lies beside the open edge of the surface at s rather than above or below it.
bool besideEdge(const Eigen::Vector3d& x, const SurfaceObservation& s, double cosine,
                double slack) {
  const Eigen::Vector3d r = x - s.point;
  const double dist = r.norm();
  return dist > slack && std::abs(s.normal.dot(r)) < cosine * dist;
}

/// Runs fn(view) over the near views, then over the others unless done() says the near
/// ones decided; views are visited in ascending order within each pass.
template <class Fn, class Done>
void overViews(const RegionViews& rv, Fn&& fn, Done&& done) {
  for (int v : rv.near()) fn(v);
  if (done()) return;
  size_t k = 0;
  for (int v = 0; v < static_cast<int>(rv.all().size()); ++v) {
    if (k < rv.near().size() && rv.near()[k] == v) {
      ++k;
      continue;
    }
    fn(v);
  }
}

}  // namespace

RegionViews::RegionViews(const std::vector<ViewIndex>& views, bool complete)
    : views_(&views), complete_(complete) {
  for (int v = 0; v < static_cast<int>(views.size()); ++v) near_.push_back(v);
}

void RegionViews::focus(const Eigen::AlignedBox3d& box, double margin) {
  centre_ = box.center();
  radius_ = 0.5 * box.diagonal().norm();
  margin_ = margin;
  near_.clear();
  SurfaceObservation o;
  for (int v = 0; v < static_cast<int>(views_->size()); ++v)
    if ((*views_)[v].closest(centre_, radius_ + margin_, o)) near_.push_back(v);
}

bool sameSurface(const Eigen::Vector3d& p0, const Eigen::Vector3d& n0, const Eigen::Vector3d& p1,
                 const Eigen::Vector3d& n1, const ConsensusParams& params) {
  return (p0 - p1).norm() <= params.sameDistance && n0.dot(n1) >= params.sameCosine;
}

SurfaceObservation consensusSurface(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                                    const RegionViews& views, const ConsensusParams& params) {
  SurfaceObservation sum;
  int count = 0;
  auto add = [&](int v) {
    SurfaceObservation o;
    if (!views.all()[v].closest(p, params.sameDistance, o)) return;  // farther fails Eq. 1
    if (!sameSurface(p, n, o.point, o.normal, params)) return;
    // A view whose surface ends beside p does not observe p: its rim point would pull the
    // average off the surface.
    if (besideEdge(p, o, params.edgeCosine, params.memberSlack)) return;
    sum.point += o.confidence * o.point;
    sum.normal += o.confidence * o.normal;
    sum.confidence += o.confidence;
    ++count;
  };
  // Views that are not near have no triangle within delta_d of p: they add nothing.
  if (views.coversBall(p, params.sameDistance)) {
    for (int v : views.near()) add(v);
  } else {
    for (int v = 0; v < static_cast<int>(views.all().size()); ++v) add(v);
  }
  if (sum.confidence > 0)
    sum.point /= sum.confidence;
  else
    sum.point = p;
  sum.normal = sum.normal.norm() > 0 ? Eigen::Vector3d(sum.normal.normalized()) : n;
  sum.views = std::max(1, count);
  return sum;
}

namespace {

struct Seed {
  SurfaceObservation o;
  int view;
};

/// Lines 5-13 of ClosestConsensusSurface over the seeds (each view's closest observation).
/// Seeds go in order of distance: a consensus point lies within delta_d of its seed, so once
/// a seed is farther than the best consensus plus delta_d no later one can win C_set; and
/// O_set only matters when C_set stays empty. Returns the view chosen, or -1.
int chooseConsensus(std::vector<Seed>& seeds, const RegionViews& views,
                    const ConsensusParams& params, const Eigen::Vector3d& x,
                    SurfaceObservation& out, bool& fromQuorum) {
  std::sort(seeds.begin(), seeds.end(), [](const Seed& a, const Seed& b) {
    return a.o.distance < b.o.distance || (a.o.distance == b.o.distance && a.view < b.view);
  });
  SurfaceObservation bestC, bestO;
  int viewC = -1, viewO = -1;
  for (const Seed& s : seeds) {
    if (viewC >= 0 && s.o.distance - params.sameDistance > bestC.distance) break;
    // Without all triangles, a seed is exact only when the ball from x out to it lies in the
    // region, and its consensus only when its delta_d ball does; closestConsensusSurface
    // answers only when the seeds skipped here cannot matter.
    if (!views.complete() &&
        (!views.coversBall(x, s.o.distance) || !views.coversBall(s.o.point, params.sameDistance)))
      continue;
    SurfaceObservation c = consensusSurface(s.o.point, s.o.normal, views, params);
    c.distance = (x - c.point).norm();
    const int v = s.view;
    if (c.confidence >= params.quorum && c.views >= params.minViews) {  // C_set: the closest
      if (viewC < 0 || c.distance < bestC.distance || (c.distance == bestC.distance && v < viewC))
        bestC = c, viewC = v;
    } else if (viewO < 0 || c.confidence > bestO.confidence ||
               (c.confidence == bestO.confidence && v < viewO)) {  // O_set: most confident
      bestO = c, viewO = v;
    }
  }
  fromQuorum = viewC >= 0;
  out = fromQuorum ? bestC : bestO;
  return fromQuorum ? viewC : viewO;
}

}  // namespace

bool closestConsensusSurface(const Eigen::Vector3d& x, const RegionViews& views,
                             const ConsensusParams& params, SurfaceObservation& out) {
  std::vector<Seed> seeds;
  auto collect = [&](int v) {
    Seed s{SurfaceObservation{}, v};
    if (views.all()[v].closest(x, params.reach, s.o)) seeds.push_back(s);
  };
  for (int v : views.near()) collect(v);
  bool fromQuorum = false;
  int chosen = chooseConsensus(seeds, views, params, x, out, fromQuorum);
  // A view that is not near has its closest point beyond the margin and so its consensus
  // beyond margin - delta_d: it cannot beat a near consensus closer than that.
  if (fromQuorum && out.distance < views.margin() - params.sameDistance) return true;
  // Routed triangles: a seed that was skipped lies over margin - delta_d from the region, so
  // its consensus is over margin - 2 delta_d away; closer than that, the answer is exact.
  if (!views.complete())
    return fromQuorum && out.distance < views.margin() - 2 * params.sameDistance;
  if (views.near().size() == views.all().size()) return chosen >= 0;
  seeds.clear();
  for (int v = 0; v < static_cast<int>(views.all().size()); ++v) collect(v);
  return chooseConsensus(seeds, views, params, x, out, fromQuorum) >= 0;
}

bool consensusSignedDistance(const Eigen::Vector3d& x, const RegionViews& views,
                             const ConsensusParams& params, SignedDistance& out) {
  SurfaceObservation s;
  if (!closestConsensusSurface(x, views, params, s)) return false;
  out = signedFrom(x, s);
  return !besideEdge(x, s, params.edgeCosine, params.edgeSlack);  // no evidence there
}

bool naiveSignedDistance(const Eigen::Vector3d& x, const RegionViews& views,
                         const ConsensusParams& params, SignedDistance& out) {
  SurfaceObservation best;
  int bestView = -1;
  auto consider = [&](int v) {
    SurfaceObservation o;
    if (!views.all()[v].closest(x, params.reach, o)) return;
    if (bestView < 0 || o.distance < best.distance || (o.distance == best.distance && v < bestView))
      best = o, bestView = v;
  };
  const auto decided = [&] { return bestView >= 0 && best.distance < views.margin(); };
  if (views.complete())
    overViews(views, consider, decided);
  else
    for (int v : views.near()) consider(v);
  if (!decided() && (!views.complete() || bestView < 0)) return false;
  out = signedFrom(x, best);
  return true;
}

}  // namespace rangefuse
