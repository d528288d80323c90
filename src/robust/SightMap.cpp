#include "rangefuse/robust/SightMap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();
constexpr float kNothing = std::numeric_limits<float>::infinity();
constexpr int kMaxSide = 8192;  // cells along a raster side; a coarser cell beyond that
// Deviations of the looking scan's own noise a point must lie in front of what it saw.
constexpr double kLookedSigmas = 3;

}  // namespace

void SightMap::markBlind(const std::array<int, 4>& lines, int k, int cols, int rows) {
  const int x0 = lines[0] / k, x1 = (cols - lines[1] + k - 1) / k;
  const int y0 = lines[2] / k, y1 = (rows - lines[3] + k - 1) / k;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if (x < x0 || x >= x1 || y < y0 || y >= y1) depthAt(x, y) = kUnknown;
}

void SightMap::forgetEnclosedHoles() {
  // Flood the holes the border reaches (views past what the frame saw) from the border inward.
  std::vector<uint8_t> open(depth_.size(), 0);
  std::vector<int32_t> queue;
  const auto flood = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    const int32_t i = y * width_ + x;
    if (depth_[i] == kNothing && !open[i]) open[i] = 1, queue.push_back(i);
  };
  for (int x = 0; x < width_; ++x) flood(x, 0), flood(x, height_ - 1);
  for (int y = 0; y < height_; ++y) flood(0, y), flood(width_ - 1, y);
  for (size_t next = 0; next < queue.size(); ++next) {
    const int x = queue[next] % width_, y = queue[next] / width_;
    flood(x - 1, y), flood(x + 1, y), flood(x, y - 1), flood(x, y + 1);
  }
  for (size_t i = 0; i < depth_.size(); ++i)
    if (depth_[i] == kNothing && !open[i]) depth_[i] = kUnknown;
}

void SightMap::allocate(int width, int height, float fill) {
  width_ = width, height_ = height;
  depth_.assign(static_cast<size_t>(width) * height, fill);
}

Eigen::Vector3d SightMap::project(const Eigen::Vector3d& q) const {
  if (rays_ == Rays::Station) {
    const double across = std::hypot(q.x(), q.y());
    return {au_ * std::atan2(q.y(), q.x()) + bu_, av_ * std::atan2(q.z(), across) + bv_,
            std::hypot(across, q.z())};
  }
  const double depth = -q.z();
  const bool pinhole = rays_ == Rays::Pinhole;
  const double X = pinhole ? q.x() / depth : q.x(), Y = pinhole ? q.y() / depth : q.y();
  return {au_ * X + bu_, av_ * Y + bv_, depth};
}

namespace {

/// The depth below which all but the farthest 0.1 % of a pinhole grid's returns lie: how far
/// its sensor reached in this frame. A few stray far returns (flying pixels) do not stretch it.
double farDepth(const RangeGrid& grid) {
  std::vector<double> depths;
  depths.reserve(grid.points.size());
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      if (const int32_t i = grid.at(r, c); i >= 0) depths.push_back(-grid.points[i].z());
  if (depths.empty()) return 0;
  const size_t k = static_cast<size_t>(0.999 * (depths.size() - 1));
  std::nth_element(depths.begin(), depths.begin() + k, depths.end());
  return depths[k];
}

/// The pixel lines at each side of a pinhole grid (left, right, top, bottom) that its sensor
/// cannot see through: a run of lines from the border, at most a sixteenth of the side,
/// without a single return, next to a line that returned in at least half its pixels. A depth
/// camera's blind band looks so (a Kinect's last 8 of 640 columns); an object seen against
/// empty space fades out over its silhouette instead.
std::array<int, 4> blindBorders(const RangeGrid& grid) {
  std::vector<int> perCol(grid.cols, 0), perRow(grid.rows, 0);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      if (grid.at(r, c) >= 0) ++perCol[c], ++perRow[r];
  const auto blind = [](const std::vector<int>& count, int length, bool fromEnd) {
    const int n = static_cast<int>(count.size());
    const auto at = [&](int i) { return count[fromEnd ? n - 1 - i : i]; };
    int run = 0;
    while (run < n && at(run) == 0) ++run;
    return run > 0 && 16 * run <= n && 2 * at(run) >= length ? run : 0;
  };
  return {blind(perCol, grid.rows, false), blind(perCol, grid.rows, true),
          blind(perRow, grid.cols, false), blind(perRow, grid.cols, true)};
}

}  // namespace

SightMap SightMap::fromPinholeGrid(const RangeGrid& grid, int k, NoReturn noReturn) {
  SightMap m;
  m.rays_ = Rays::Pinhole;
  k = std::max(1, k);
  // Pixel c = cx + fx x / depth has its centre at integer c; block C holds [k C, k C + k).
  const Pinhole& p = *grid.pinhole;
  m.au_ = p.fx / k, m.bu_ = (p.cx + 0.5) / k;
  m.av_ = p.fy / k, m.bv_ = (p.cy + 0.5) / k;
  m.allocate((grid.cols + k - 1) / k, (grid.rows + k - 1) / k, kNothing);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const int32_t i = grid.at(r, c);
      if (i < 0) continue;
      float& d = m.depthAt(c / k, r / k);
      d = std::min(d, static_cast<float>(-grid.points[i].z()));
    }
  if (noReturn == NoReturn::DepthCamera) {
    m.reach_ = farDepth(grid);
    m.markBlind(blindBorders(grid), k, grid.cols, grid.rows);
    m.forgetEnclosedHoles();
  }
  return m;
}

namespace {

/// x = a col + b and y = c row + d fitted to a near-orthographic grid's points (scan frame),
/// so that its cells without a return have a place too. False when the grid is not that
/// regular (the fit is off by more than a quarter of a cell somewhere in its bulk).
bool fitGridLattice(const RangeGrid& grid, Eigen::Vector4d& fit) {
  double s[2][5] = {};  // per axis: n, sum i, sum i^2, sum v, sum i v
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const int32_t i = grid.at(r, c);
      if (i < 0) continue;
      const double idx[2] = {double(c), double(r)},
                   val[2] = {grid.points[i].x(), grid.points[i].y()};
      for (int a = 0; a < 2; ++a) {
        s[a][0] += 1, s[a][1] += idx[a], s[a][2] += idx[a] * idx[a];
        s[a][3] += val[a], s[a][4] += idx[a] * val[a];
      }
    }
  for (int a = 0; a < 2; ++a) {
    const double det = s[a][0] * s[a][2] - s[a][1] * s[a][1];
    if (s[a][0] < 16 || !(std::abs(det) > 0)) return false;
    fit[2 * a] = (s[a][0] * s[a][4] - s[a][1] * s[a][3]) / det;
    fit[2 * a + 1] = (s[a][3] - fit[2 * a] * s[a][1]) / s[a][0];
  }
  std::vector<double> off;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      if (const int32_t i = grid.at(r, c); i >= 0)
        off.push_back(
            std::max(std::abs(grid.points[i].x() - fit[0] * c - fit[1]) / std::abs(fit[0]),
                     std::abs(grid.points[i].y() - fit[2] * r - fit[3]) / std::abs(fit[2])));
  auto q = off.begin() + static_cast<std::ptrdiff_t>(0.9 * static_cast<double>(off.size()));
  std::nth_element(off.begin(), q, off.end());
  return *q < 0.25;
}

}  // namespace

SightMap SightMap::fromSurface(const ScanSurface& surface, double cell, const RangeGrid* grid) {
  SightMap m;
  if (surface.points.empty() || !(cell > 0)) return m;
  Eigen::AlignedBox2d box;
  for (const auto& q : surface.points) box.extend(q.head<2>());
  Eigen::Vector4d fit;
  const bool lattice = grid && fitGridLattice(*grid, fit);
  if (lattice) {  // the raster spans the grid's whole frame, returns or not
    box.extend(Eigen::Vector2d(fit[1], fit[3]));
    box.extend(
        Eigen::Vector2d(fit[0] * (grid->cols - 1) + fit[1], fit[2] * (grid->rows - 1) + fit[3]));
  }
  cell = std::max(cell, box.sizes().maxCoeff() / (kMaxSide - 4));
  m.au_ = m.av_ = 1 / cell;
  m.bu_ = 2 - box.min().x() / cell, m.bv_ = 2 - box.min().y() / cell;
  m.allocate(static_cast<int>(std::ceil(box.sizes().x() / cell)) + 4,
             static_cast<int>(std::ceil(box.sizes().y() / cell)) + 4, kUnknown);
  const auto& v = surface.points;
  for (const Triangle& t : surface.triangles)
    m.rasterize(m.project(v[t[0]]), m.project(v[t[1]]), m.project(v[t[2]]));
  if (lattice) m.markNoReturns(*grid, fit);
  m.cropUnknown();
  return m;
}

void SightMap::markNoReturns(const RangeGrid& grid, const Eigen::Vector4d& fit) {
  // A raster cell saw nothing when every grid cell in it got no return and no triangle covers
  // it: a point without triangles (filtered out) still says something is there.
  std::vector<uint8_t> returned(depth_.size(), 0);
  std::vector<size_t> empty;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const Eigen::Vector3d at = project({fit[0] * c + fit[1], fit[2] * r + fit[3], 0});
      const int x = static_cast<int>(std::floor(at.x())), y = static_cast<int>(std::floor(at.y()));
      if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;
      const size_t i = static_cast<size_t>(y) * width_ + x;
      if (grid.at(r, c) >= 0)
        returned[i] = 1;
      else
        empty.push_back(i);
    }
  for (const size_t i : empty)
    if (!returned[i] && std::isnan(depth_[i])) depth_[i] = kNothing;
}

SightMap SightMap::fromStation(const ScanSurface& surface, double angle) {
  SightMap m;
  if (surface.points.empty() || !(angle > 0)) return m;
  m.rays_ = Rays::Station;
  angle = std::max(angle, 2 * M_PI / (kMaxSide - 4));
  // Two cells of margin around [-pi, pi] x [-pi/2, pi/2], as fromSurface keeps around its box.
  m.au_ = m.av_ = 1 / angle;
  m.bu_ = 2 + M_PI / angle, m.bv_ = 2 + 0.5 * M_PI / angle;
  m.allocate(static_cast<int>(std::ceil(2 * M_PI / angle)) + 4,
             static_cast<int>(std::ceil(M_PI / angle)) + 4, kUnknown);
  const auto& v = surface.points;
  const double seam = M_PI / angle;  // a triangle spanning half a turn lies across the seam
  for (const Triangle& t : surface.triangles) {
    const Eigen::Vector3d a = m.project(v[t[0]]), b = m.project(v[t[1]]), c = m.project(v[t[2]]);
    if (std::max({a.x(), b.x(), c.x()}) - std::min({a.x(), b.x(), c.x()}) < seam)
      m.rasterize(a, b, c);
  }
  m.cropUnknown();
  return m;
}

void SightMap::cropUnknown() {
  int x0 = width_, x1 = -1, y0 = height_, y1 = -1;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if (!std::isnan(depthAt(x, y)))
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  if (x1 < 0) x0 = y0 = 0, x1 = y1 = -1;  // nothing known: an empty raster
  if (x0 == 0 && y0 == 0 && x1 == width_ - 1 && y1 == height_ - 1) return;
  SightMap out = *this;
  out.allocate(x1 - x0 + 1, y1 - y0 + 1, kUnknown);
  for (int y = y0; y <= y1; ++y)
    std::copy_n(&depth_[static_cast<size_t>(y) * width_ + x0], out.width_,
                &out.depth_[static_cast<size_t>(y - y0) * out.width_]);
  out.bu_ -= x0, out.bv_ -= y0;
  *this = std::move(out);
}

void SightMap::place(const Pose& pose) {
  toScan_ = pose.inverse();
}

void SightMap::join(SightMap&& other) {
  if (depth_.empty()) {
    *this = std::move(other);
    return;
  }
  if (other.depth_.empty()) return;
  // Cropped from the same raster, the two differ by whole cells: other's (x, y) is ours + shift.
  const double sx = bu_ - other.bu_, sy = bv_ - other.bv_;
  const long dx = std::lround(sx), dy = std::lround(sy);
  if (other.rays_ != rays_ || other.au_ != au_ || other.av_ != av_ || sx != dx || sy != dy)
    throw std::logic_error("SightMap::join: the maps are on different rasters");
  const int x0 = static_cast<int>(std::min<long>(0, dx)),
            y0 = static_cast<int>(std::min<long>(0, dy));
  const int x1 = static_cast<int>(std::max<long>(width_, dx + other.width_));
  const int y1 = static_cast<int>(std::max<long>(height_, dy + other.height_));
  SightMap out = *this;
  out.allocate(x1 - x0, y1 - y0, kUnknown);
  out.bu_ -= x0, out.bv_ -= y0;
  auto add = [&](const SightMap& m, int ox, int oy) {
    for (int y = 0; y < m.height_; ++y)
      for (int x = 0; x < m.width_; ++x) {
        const float d = m.depthAt(x, y);
        float& to = out.depthAt(x + ox, y + oy);
        if (std::isnan(to) || d < to) to = d;
      }
  };
  add(*this, -x0, -y0);
  add(other, static_cast<int>(dx) - x0, static_cast<int>(dy) - y0);
  *this = std::move(out);
}

void SightMap::rasterize(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c) {
  auto keepNearest = [&](int x, int y, double depth) {
    float& d = depthAt(x, y);
    if (!(d <= depth)) d = static_cast<float>(depth);  // NaN (unknown) or farther
  };
  // Each corner marks its own cell, so that triangles smaller than a cell leave no gaps.
  for (const auto* p : {&a, &b, &c})
    keepNearest(static_cast<int>(p->x()), static_cast<int>(p->y()), p->z());
  const double area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  if (!(std::abs(area) > 0)) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
  const int x1 = std::min(width_ - 1, static_cast<int>(std::max({a.x(), b.x(), c.x()})));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::max({a.y(), b.y(), c.y()})));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;  // the cell's centre
      const double wa = ((b.x() - px) * (c.y() - py) - (c.x() - px) * (b.y() - py)) / area;
      const double wb = ((c.x() - px) * (a.y() - py) - (a.x() - px) * (c.y() - py)) / area;
      const double wc = 1 - wa - wb;
      if (wa < 0 || wb < 0 || wc < 0) continue;
      keepNearest(x, y, wa * a.z() + wb * b.z() + wc * c.z());
    }
}

double SightMap::clearance(const Eigen::Vector3d& p) const {
  double depth;
  return clearanceAt(p, depth);
}

double SightMap::clearanceAt(const Eigen::Vector3d& p, double& depth) const {
  const Eigen::Vector3d q = toScan_.apply(p);
  if (rays_ == Rays::Pinhole && !(q.z() < 0)) return NAN;  // behind the sensor
  const Eigen::Vector3d r = project(q);
  depth = r.z();
  if (!(r.x() >= 1 && r.y() >= 1 && r.x() < width_ - 1 && r.y() < height_ - 1)) return NAN;
  const int x = static_cast<int>(r.x()), y = static_cast<int>(r.y());
  float nearest = kNothing;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float d = depthAt(x + dx, y + dy);
      if (std::isnan(d)) return NAN;
      nearest = std::min(nearest, d);
    }
  if (nearest == kNothing && r.z() > reach_) return NAN;  // out of the sensor's reach
  return nearest - r.z();
}

void SightMap::setNoise(RangeNoise noise, double sampleShare) {
  noise_ = std::move(noise);
  sampleShare_ = sampleShare;
}

double SightMap::noiseAt(const Eigen::Vector3d& p) const {
  if (noise_.empty()) return 0;
  return noise_.at(project(toScan_.apply(p)).z());
}

bool SightMap::lookedThrough(const Eigen::Vector3d& p, double margin) const {
  return sightOf(p, margin) == Sight::Through;
}

SightMap::Sight SightMap::sightOf(const Eigen::Vector3d& p, double margin) const {
  double depth = 0;
  const double clear = clearanceAt(p, depth);
  if (clear < 0) return Sight::Behind;
  if (clear > margin && clear > margin + kLookedSigmas * noise_.at(depth)) return Sight::Through;
  return Sight::Unknown;  // NaN (unknown, behind the sensor) too
}

bool SightMap::mayCover(const Eigen::AlignedBox3d& box) const {
  if (rays_ == Rays::Station) return true;  // azimuths wrap: not worth bounding
  Eigen::AlignedBox2d seen;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d q =
        toScan_.apply(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
    // A corner at or behind the sensor's plane: the box's image is unbounded.
    if (rays_ == Rays::Pinhole && !(q.z() < 0)) return true;
    // Orthographic and (all corners in front) perspective images of the box lie in the
    // bounds of its corners' images.
    seen.extend(project(q).head<2>());
  }
  // clearance() answers only for cells in [1, width - 1) x [1, height - 1).
  return seen.max().x() >= 1 && seen.min().x() < width_ - 1 && seen.max().y() >= 1 &&
         seen.min().y() < height_ - 1;
}

void SightMap::pack(std::vector<char>& out) const {
  double head[18] = {static_cast<double>(rays_), au_, bu_, av_, bv_};
  for (int i = 0; i < 9; ++i) head[5 + i] = toScan_.R(i / 3, i % 3);
  for (int i = 0; i < 3; ++i) head[14 + i] = toScan_.t[i];
  head[17] = reach_;
  const int32_t size[2] = {width_, height_};
  mpi::pack(out, head, 18);
  mpi::pack(out, size, 2);
  mpi::pack(out, depth_.data(), depth_.size());
  const int32_t points = static_cast<int32_t>(noise_.depths().size());
  mpi::pack(out, &points, 1);
  mpi::pack(out, noise_.depths().data(), points);
  mpi::pack(out, noise_.sigmas().data(), points);
  mpi::pack(out, &sampleShare_, 1);
}

SightMap SightMap::unpack(const std::vector<char>& in, size_t& pos) {
  double head[18];
  int32_t size[2];
  mpi::unpack(in, pos, head, 18);
  mpi::unpack(in, pos, size, 2);
  SightMap m;
  if (!(head[0] == 0 || head[0] == 1 || head[0] == 2))
    throw std::runtime_error("sight map: unknown kind of rays in a message");
  m.rays_ = static_cast<Rays>(static_cast<int>(head[0]));
  m.au_ = head[1], m.bu_ = head[2], m.av_ = head[3], m.bv_ = head[4];
  for (int i = 0; i < 9; ++i) m.toScan_.R(i / 3, i % 3) = head[5 + i];
  for (int i = 0; i < 3; ++i) m.toScan_.t[i] = head[14 + i];
  m.reach_ = head[17];
  m.allocate(size[0], size[1], kUnknown);
  mpi::unpack(in, pos, m.depth_.data(), m.depth_.size());
  int32_t points = 0;
  mpi::unpack(in, pos, &points, 1);
  if (points < 0 || points > 1024)
    throw std::runtime_error("sight map: bad noise curve in a message");
  std::vector<double> depths(points), sigmas(points);
  mpi::unpack(in, pos, depths.data(), points);
  mpi::unpack(in, pos, sigmas.data(), points);
  m.noise_ = RangeNoise::fromPoints(std::move(depths), std::move(sigmas));
  mpi::unpack(in, pos, &m.sampleShare_, 1);
  return m;
}

}  // namespace rangefuse
