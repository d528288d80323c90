#include "rangefuse/scan/DepthSensorModel.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

/// True when a neighbour within one pixel lies more than 10 % nearer or farther: the pixel is
/// on a depth edge (the window jobs/sensor_statistics.py uses to count edges, at radius 1).
bool onEdge(const std::vector<double>& d, int cols, int rows, int r, int c) {
  const double z = d[static_cast<size_t>(r) * cols + c];
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc) {
      const int rr = r + dr, cc = c + dc;
      if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
      const double o = d[static_cast<size_t>(rr) * cols + cc];
      if (o > 0 && std::abs(o - z) > 0.1 * std::min(o, z)) return true;
    }
  return false;
}

/// The nearest and farthest depth within one pixel of (r, c).
std::pair<double, double> sides(const std::vector<double>& d, int cols, int rows, int r, int c) {
  double lo = INFINITY, hi = 0;
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc) {
      const int rr = r + dr, cc = c + dc;
      if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
      const double o = d[static_cast<size_t>(rr) * cols + cc];
      if (o > 0) lo = std::min(lo, o), hi = std::max(hi, o);
    }
  return {lo, hi};
}

}  // namespace

DepthSensorModel DepthSensorModel::preset(const std::string& name) {
  DepthSensorModel m;
  if (name == "none") return m;
  if (name != "kinect") throw InputError("scan: --sensor must be kinect or none");
  // Kinect v1, checked against 1000 frames of 7-Scenes (docs/sensor.md): depth steps of
  // z^2 / (f b) / 8 with a 7.5 cm baseline match the steps measured there (10 mm at 1.9 m);
  // the disparity noise gives the measured noise by depth; holes and mixed returns at edges,
  // the blank band and the range are the measured ones.
  m.baseline = 0.075;
  m.disparityNoise = 0.015;
  m.nearest = 0.8, m.farthest = 3.5;
  m.grazingCos = 0.15;
  m.darkShare = 0.03, m.darkCell = 0.15;
  m.edgeHoles = 0.02;
  m.flying = 0.01;
  m.blankColumns = 8;
  // Not measurable without poses between frames: a rolling shutter read over half a frame
  // and depth 10 ms late, as reported for TUM RGB-D's Kinects.
  m.rollingShutter = 0.5;
  m.timeOffset = 0.3;
  return m;
}

std::string faultNames() {
  static const char* names[] = {"noise", "steps", "shadows", "grazing", "dark",
                                "edges", "band",  "range",   "shutter", "offset"};
  std::string words;
  for (size_t k = 0; k < std::size(names); ++k)
    words += (k == 0 ? "" : k + 1 == std::size(names) ? " or " : ", ") + std::string(names[k]);
  return words;
}

DepthSensorModel DepthSensorModel::without(const std::string& list) const {
  DepthSensorModel m = *this;
  size_t start = 0;
  while (start <= list.size() && !list.empty()) {
    const size_t end = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, end - start);
    start = end + 1;
    if (name == "noise")
      m.disparityNoise = 0;
    else if (name == "steps")
      m.quantum = 0;
    else if (name == "shadows")
      m.shadows = false;
    else if (name == "grazing")
      m.grazingCos = 0;
    else if (name == "dark")
      m.darkShare = 0;
    else if (name == "edges")
      m.edgeHoles = m.flying = 0;
    else if (name == "band")
      m.blankColumns = 0;
    else if (name == "range")
      m.nearest = m.farthest = 0;
    else if (name == "shutter")
      m.rollingShutter = 0;
    else if (name == "offset")
      m.timeOffset = 0;
    else
      throw InputError("scan: --sensor-without: '" + name + "' is not " + faultNames());
  }
  return m;
}

bool onDarkSurface(double x, double y, double z, const DepthSensorModel& m) {
  if (!(m.darkShare > 0 && m.darkCell > 0)) return false;
  const auto cell = [&](double v) {
    return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v / m.darkCell)));
  };
  // SplitMix64 of the cell's three indices: a fixed pattern on the surface.
  uint64_t h = cell(x) * 0x9E3779B97F4A7C15ull ^ cell(y) * 0xC2B2AE3D27D4EB4Full ^
               cell(z) * 0x165667B19E3779F9ull;
  h ^= h >> 30, h *= 0xBF58476D1CE4E5B9ull, h ^= h >> 27, h *= 0x94D049BB133111EBull, h ^= h >> 31;
  return static_cast<double>(h >> 11) * 0x1.0p-53 < m.darkShare;
}

void applyImageFaults(std::vector<double>& depth, int cols, int rows, double fx,
                      const DepthSensorModel& m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  const std::vector<double> clean = depth;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      double& z = depth[static_cast<size_t>(r) * cols + c];
      if (!(z > 0) || !onEdge(clean, cols, rows, r, c)) continue;
      const double u = unit(rng);
      if (u < m.edgeHoles) {
        z = 0;
      } else if (u < m.edgeHoles + m.flying) {
        const auto [lo, hi] = sides(clean, cols, rows, r, c);
        z = lo + unit(rng) * (hi - lo);
      }
    }
  const int blank = static_cast<int>(std::lround(m.blankColumns * cols / 640.0));
  for (int r = 0; r < rows; ++r)
    for (int c = cols - blank; c < cols; ++c) depth[static_cast<size_t>(r) * cols + c] = 0;
  const double fb = fx * m.baseline;
  std::normal_distribution<double> noise(0, m.disparityNoise);
  for (double& z : depth) {
    if (!(z > 0)) continue;
    double disparity = fb / z + (m.disparityNoise > 0 ? noise(rng) : 0);
    if (m.quantum > 0) disparity = std::round(disparity / m.quantum) * m.quantum;
    z = disparity > 0 ? fb / disparity : 0;
  }
}

}  // namespace rangefuse
