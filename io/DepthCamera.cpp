#include "rangefuse/io/DepthCamera.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "TextLines.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Json.h"

namespace rangefuse::io {
namespace {

/// Half a turn about x: maps the camera's (x right, y down, +z forward) to the scan frame's
/// (x right, y up, sensor looking toward -z); its own inverse.
const Eigen::Matrix3d& flip() {
  static const Eigen::Matrix3d m = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return m;
}

void checkCamera(const std::string& where, const DepthCamera& c) {
  for (double v : {c.fx, c.fy, c.cx, c.cy})
    if (!std::isfinite(v)) throw InputError(where + ": intrinsics must be finite numbers");
  if (!(c.fx > 0 && c.fy > 0))
    throw InputError(where + ": focal lengths fx and fy must be positive pixels");
  if (c.width < 0 || c.height < 0) throw InputError(where + ": width and height must be >= 0");
}

constexpr double kImplausibleDepth = 100;  // metres

std::string formatDepthScale(double unit) {
  std::ostringstream s;
  s << 1 / unit;
  return s.str();
}

}  // namespace

RangeGrid depthGrid(const DepthImage& image, const DepthCamera& camera, const std::string& path) {
  if ((camera.width && camera.width != image.width) ||
      (camera.height && camera.height != image.height))
    throw InputError(path + ": image is " + std::to_string(image.width) + " x " +
                     std::to_string(image.height) + " pixels but the camera's intrinsics are for " +
                     std::to_string(camera.width) + " x " + std::to_string(camera.height));
  RangeGrid g;
  g.cols = image.width;
  g.rows = image.height;
  g.cell.assign(static_cast<size_t>(g.cols) * g.rows, -1);
  g.pinhole = Pinhole{camera.fx, camera.fy, camera.cx, image.height - 1 - camera.cy};
  // Sized once: grown by doubling, a frame's points were copied about twice over.
  g.points.reserve(image.counts.size() -
                   std::count(image.counts.begin(), image.counts.end(), uint16_t{0}));
  size_t measured = 0, tooFar = 0;
  // x and y divided by fx and fy in one packed division: each lane rounds as its own would.
  const Eigen::Array2d focal(camera.fx, camera.fy);
  for (int r = 0; r < g.rows; ++r) {
    const int v = g.rows - 1 - r;
    for (int u = 0; u < g.cols; ++u) {
      const uint16_t count = image.at(u, v);
      const double d = count * camera.unit;
      measured += count > 0;
      tooFar += d > kImplausibleDepth;
      if (count == 0 || (camera.depthMax > 0 && d > camera.depthMax)) continue;
      g.cell[static_cast<size_t>(r) * g.cols + u] = static_cast<int32_t>(g.points.size());
      const Eigen::Array2d xy = Eigen::Array2d((u - camera.cx) * d, (camera.cy - v) * d) / focal;
      g.points.emplace_back(xy.x(), xy.y(), -d);
    }
  }
  // A depth unit off by a factor of 1000 (counts read as metres) puts every depth kilometres
  // away; no depth camera measures past tens of metres.
  if (measured > 0 && tooFar == measured)
    throw InputError(path + ": every depth lies beyond " + std::to_string(int(kImplausibleDepth)) +
                     " m at " + formatDepthScale(camera.unit) +
                     " counts a metre: is --depth-scale right?");
  return g;
}

void colourFromImage(RangeGrid& grid, const Image& colour, const std::string& path) {
  if (colour.width != grid.cols || colour.height != grid.rows)
    throw InputError(path + ": colour image is " + std::to_string(colour.width) + " x " +
                     std::to_string(colour.height) + " pixels but its depth image is " +
                     std::to_string(grid.cols) + " x " + std::to_string(grid.rows));
  grid.colourKind = ColourKind::rgb;
  grid.colours.assign(grid.points.size(), Colour::Zero());
  for (int r = 0; r < grid.rows; ++r)
    for (int u = 0; u < grid.cols; ++u) {
      const int32_t k = grid.at(r, u);
      if (k < 0) continue;
      const uint8_t* p = &colour.rgb[(static_cast<size_t>(grid.rows - 1 - r) * grid.cols + u) * 3];
      grid.colours[k] = Colour(p[0], p[1], p[2]) / 255;
    }
}

Image colourImage(const RangeGrid& grid) {
  Image image(grid.cols, grid.rows, 0);
  for (int r = 0; r < grid.rows; ++r)
    for (int u = 0; u < grid.cols; ++u) {
      const int32_t k = grid.at(r, u);
      if (k < 0) continue;
      const Colour& c = grid.colours[k];
      image.set(u, grid.rows - 1 - r, colourByte(c[0]), colourByte(c[1]), colourByte(c[2]));
    }
  return image;
}

DepthImage depthImage(const RangeGrid& g, double unit) {
  DepthImage image{g.cols, g.rows, std::vector<uint16_t>(g.cell.size(), 0)};
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      if (g.at(r, c) < 0) continue;
      const double counts = std::round(-g.points[g.at(r, c)].z() / unit);
      if (counts >= 1 && counts <= 65535)
        image.counts[static_cast<size_t>(g.rows - 1 - r) * g.cols + c] =
            static_cast<uint16_t>(counts);
    }
  return image;
}

DepthCamera depthCamera(const RangeGrid& g, double unit) {
  DepthCamera c;
  c.fx = g.pinhole->fx, c.fy = g.pinhole->fy, c.cx = g.pinhole->cx;
  c.cy = g.rows - 1 - g.pinhole->cy;
  c.width = g.cols, c.height = g.rows, c.unit = unit;
  return c;
}

Pose scanPose(const Pose& cameraToWorld) {
  return Pose{cameraToWorld.R * flip(), cameraToWorld.t};
}

Pose cameraPose(const Pose& scanToWorld) {
  return Pose{scanToWorld.R * flip(), scanToWorld.t};
}

DepthCamera readIntrinsicJson(const std::string& path) {
  const nlohmann::json j = readJson(path);
  DepthCamera c;
  try {
    const auto& k = j.at("intrinsic_matrix");
    if (!k.is_array() || k.size() != 9)
      throw InputError(path + ": intrinsic_matrix must hold 9 numbers (column major)");
    c.fx = k[0].get<double>();
    c.fy = k[4].get<double>();
    c.cx = k[6].get<double>();
    c.cy = k[7].get<double>();
    c.width = j.at("width").get<int>();
    c.height = j.at("height").get<int>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(
        path + ": not a camera intrinsic file (width, height, intrinsic_matrix): " + e.what());
  }
  checkCamera(path, c);
  return c;
}

DepthCamera readIntrinsicMatrix(const std::string& path) {
  const auto rows = internal::squareRows(path, 3, "a 3 x 3 camera matrix K");
  Eigen::Matrix3d k;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) k(r, c) = rows[r][c];
  if (k(0, 1) != 0 || k(1, 0) != 0 || k(2, 0) != 0 || k(2, 1) != 0 || k(2, 2) != 1)
    throw InputError(path +
                     ": not a pinhole camera matrix (expected 'fx 0 cx', '0 fy cy', "
                     "'0 0 1')");
  DepthCamera c;
  c.fx = k(0, 0), c.fy = k(1, 1), c.cx = k(0, 2), c.cy = k(1, 2);
  checkCamera(path, c);
  return c;
}

void writeIntrinsicJson(const std::string& path, const DepthCamera& c) {
  writeJson(path, {{"width", c.width},
                   {"height", c.height},
                   {"intrinsic_matrix", {c.fx, 0, 0, 0, c.fy, 0, c.cx, c.cy, 1}}});
}

DepthCamera parseIntrinsics(const std::string& text) {
  if (text.find(',') == std::string::npos)
    return text.size() > 4 && text.substr(text.size() - 4) == ".txt" ? readIntrinsicMatrix(text)
                                                                     : readIntrinsicJson(text);
  DepthCamera c;
  std::istringstream in(text);
  char comma1 = 0, comma2 = 0, comma3 = 0;
  if (!(in >> c.fx >> comma1 >> c.fy >> comma2 >> c.cx >> comma3 >> c.cy) || comma1 != ',' ||
      comma2 != ',' || comma3 != ',' || !(in >> std::ws).eof())
    throw InputError("--intrinsics: '" + text + "' is not fx,fy,cx,cy (pixels) or a file");
  checkCamera("--intrinsics", c);
  return c;
}

}  // namespace rangefuse::io
