// An E57 scan's records as a spherical range grid.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "E57Records.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/KdTree.h"
#include "rangefuse/io/E57.h"

namespace rangefuse::io {

using internal::E57Pages;
using internal::E57Records;

namespace {

/// Which prototype field carries what the grid needs (-1: none).
struct FieldRoles {
  int coordinate[3] = {-1, -1, -1};
  int invalid = -1, row = -1, column = -1, intensity = -1, colour[3] = {-1, -1, -1};

  explicit FieldRoles(const E57Scan& scan) {
    const char* cartesian[3] = {"cartesianX", "cartesianY", "cartesianZ"};
    const char* spherical[3] = {"sphericalRange", "sphericalAzimuth", "sphericalElevation"};
    const char* colours[3] = {"colorRed", "colorGreen", "colorBlue"};
    for (int i = 0; i < static_cast<int>(scan.fields.size()); ++i) {
      const std::string& n = scan.fields[i].name;
      for (int a = 0; a < 3; ++a) {
        if (n == (scan.spherical ? spherical[a] : cartesian[a])) coordinate[a] = i;
        if (n == colours[a]) colour[a] = i;
      }
      if (n == (scan.spherical ? "sphericalInvalidState" : "cartesianInvalidState")) invalid = i;
      if (n == "rowIndex") row = i;
      if (n == "columnIndex") column = i;
      if (n == "intensity") intensity = i;
    }
    if (scan.intensity && intensity >= 0) colour[0] = colour[1] = colour[2] = -1;
  }

  bool rgb() const { return colour[0] >= 0 && colour[1] >= 0 && colour[2] >= 0; }

  std::vector<bool> wanted(size_t fields) const {
    std::vector<bool> w(fields, false);
    for (int i : {coordinate[0], coordinate[1], coordinate[2], invalid, row, column, intensity,
                  colour[0], colour[1], colour[2]})
      if (i >= 0) w[static_cast<size_t>(i)] = true;
    return w;
  }
};

/// The points, colours and (structured scans) cells of a scan's valid records, in record order.
struct Returns {
  std::vector<Eigen::Vector3d> points;
  std::vector<Colour> colours;
  std::vector<std::pair<int, int>> cells;  ///< row and column of each point
};

float normalised(double v, double lo, double hi) {
  return static_cast<float>(std::clamp((v - lo) / (hi - lo), 0.0, 1.0));
}

/// Reads the valid records whose column lies in [first, first + count) (any column when the
/// scan has no indices).
Returns readReturns(const std::string& path, const E57Scan& scan, const FieldRoles& f, int first,
                    int count) {
  E57Pages pages(path);
  Returns out;
  const bool structured = f.row >= 0 && f.column >= 0 && scan.rows > 0;
  // Room for every record of the columns read, so that the vectors never grow by copying.
  const uint64_t expected =
      structured ? scan.records * uint64_t(count) / uint64_t(scan.cols) : scan.records;
  out.points.reserve(expected), out.cells.reserve(expected);
  if (f.rgb() || f.intensity >= 0) out.colours.reserve(expected);
  uint64_t record = 0;
  internal::decodeE57Records(pages, scan, f.wanted(scan.fields.size()), [&](const E57Records& c) {
    for (size_t i = 0; i < c.count; ++i, ++record) {
      if (f.invalid >= 0 && c.values[f.invalid][i] != 0) continue;
      int r = 0, col = 0;
      if (structured) {
        const double rr = c.values[f.row][i] - double(scan.firstRow);
        const double cc = c.values[f.column][i] - double(scan.firstColumn);
        if (!(rr >= 0 && rr < scan.rows && cc >= 0 && cc < scan.cols))
          throw InputError(path + ": " + scan.name + ": record " + std::to_string(record) +
                           ": row " + std::to_string(int64_t(c.values[f.row][i])) + ", column " +
                           std::to_string(int64_t(c.values[f.column][i])) +
                           " outside the stated index bounds");
        r = static_cast<int>(rr), col = static_cast<int>(cc) - first;
        if (col < 0 || col >= count) continue;
      }
      Eigen::Vector3d p(c.values[f.coordinate[0]][i], c.values[f.coordinate[1]][i],
                        c.values[f.coordinate[2]][i]);
      if (scan.spherical) {
        const double range = p[0], az = p[1], el = p[2];
        p = range *
            Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      }
      if (!p.allFinite())
        throw InputError(path + ": " + scan.name + ": record " + std::to_string(record) +
                         ": non-finite coordinate");
      if (p.isZero(0)) continue;  // no return
      out.points.push_back(p);
      out.cells.emplace_back(r, col);
      if (f.rgb())
        out.colours.emplace_back(
            normalised(c.values[f.colour[0]][i], scan.colourMin, scan.colourMax),
            normalised(c.values[f.colour[1]][i], scan.colourMin, scan.colourMax),
            normalised(c.values[f.colour[2]][i], scan.colourMin, scan.colourMax));
      else if (f.intensity >= 0)
        out.colours.push_back(Colour::Constant(
            normalised(c.values[f.intensity][i], scan.intensityMin, scan.intensityMax)));
    }
  });
  return out;
}

/// The returns on a grid of rows x cols, points in column-major order (as a PTX station's);
/// a cell hit twice keeps its first return.
RangeGrid gridOf(Returns&& in, int rows, int cols, ColourKind kind) {
  RangeGrid g;
  g.rows = rows, g.cols = cols, g.spherical = true;
  std::vector<int32_t> record(static_cast<size_t>(rows) * cols, -1);
  for (size_t k = 0; k < in.cells.size(); ++k) {
    int32_t& slot = record[static_cast<size_t>(in.cells[k].first) * cols + in.cells[k].second];
    if (slot < 0) slot = static_cast<int32_t>(k);
  }
  g.cell.assign(record.size(), -1);
  for (int c = 0; c < cols; ++c)
    for (int r = 0; r < rows; ++r) {
      const int32_t k = record[static_cast<size_t>(r) * cols + c];
      if (k < 0) continue;
      g.cell[static_cast<size_t>(r) * cols + c] = static_cast<int32_t>(g.points.size());
      g.points.push_back(in.points[k]);
      if (!in.colours.empty()) g.colours.push_back(in.colours[k]);
    }
  g.colourKind = g.colours.empty() ? ColourKind::none : kind;
  return g;
}

/// The typical angle between neighbouring returns seen from the origin: the median, over up to
/// 20000 returns, of the angle to the fourth nearest other return in direction. On a regular
/// grid that is the grid's step (four neighbours at one step); on scattered returns it leaves
/// about one return a cell.
double neighbourAngle(const std::vector<Eigen::Vector3d>& points) {
  PointCloud directions;
  directions.pts.reserve(points.size());
  for (const Eigen::Vector3d& p : points) directions.pts.push_back(p.normalized());
  const std::unique_ptr<KdTree> tree = buildKdTree(directions);
  std::vector<double> angles;
  const size_t stride = std::max<size_t>(1, points.size() / 20000);
  for (size_t i = 0; i < points.size(); i += stride) {
    unsigned ids[5];
    double squared[5];
    const size_t found = tree->knnSearch(directions.pts[i].data(), 5, ids, squared);
    if (found == 5 && squared[4] > 1e-18)
      angles.push_back(std::sqrt(squared[4]));  // the chord: the angle, for small angles
  }
  if (angles.empty()) return 0;
  std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
  return angles[angles.size() / 2];
}

/// Rows and columns for a scan without indices: azimuth and elevation around the origin on a
/// square angular step, the typical angle between neighbouring returns; each return goes to
/// its nearest cell (a cell hit twice keeps its first return).
RangeGrid projected(Returns&& in, uint64_t maxCells, ColourKind kind, double& stepDeg) {
  double azLo = M_PI, azHi = -M_PI, elLo = M_PI, elHi = -M_PI;
  std::vector<std::pair<double, double>> angles;
  angles.reserve(in.points.size());
  for (const Eigen::Vector3d& p : in.points) {
    const double az = std::atan2(p.y(), p.x()), el = std::atan2(p.z(), p.head<2>().norm());
    angles.emplace_back(az, el);
    azLo = std::min(azLo, az), azHi = std::max(azHi, az);
    elLo = std::min(elLo, el), elHi = std::max(elHi, el);
  }
  const double step = neighbourAngle(in.points);
  if (!(step > 0)) return gridOf(std::move(in), 1, 1, kind);
  stepDeg = step * 180 / M_PI;
  const int cols = std::max(1, static_cast<int>(std::ceil((azHi - azLo) / step)) + 1);
  const int rows = std::max(1, static_cast<int>(std::ceil((elHi - elLo) / step)) + 1);
  checkLimit("spherical projection", "grid cells", double(rows) * cols, maxCells, "max-grid-cells");
  for (size_t k = 0; k < angles.size(); ++k)
    in.cells[k] = {static_cast<int>(std::lround((angles[k].second - elLo) / step)),
                   static_cast<int>(std::lround((angles[k].first - azLo) / step))};
  return gridOf(std::move(in), rows, cols, kind);
}

}  // namespace

RangeGrid readE57Scan(const std::string& path, const E57Scan& scan, std::string* warning) {
  const FieldRoles f(scan);
  if (f.row >= 0 && f.column >= 0 && scan.rows > 0) return readE57Columns(path, scan, 0, scan.cols);
  const ColourKind kind = f.rgb()            ? ColourKind::rgb
                          : f.intensity >= 0 ? ColourKind::intensity
                                             : ColourKind::none;
  double step = 0;
  RangeGrid g = projected(readReturns(path, scan, f, 0, 1), InputLimits{}.maxGridCells, kind, step);
  if (warning && step > 0) {
    std::ostringstream w;
    w << path << ": " << scan.name << ": no row and column indices; gridded by spherical "
      << "projection at an estimated step of " << step << " degrees";
    *warning = w.str();
  }
  return g;
}

RangeGrid readE57Columns(const std::string& path, const E57Scan& scan, int first, int count) {
  const FieldRoles f(scan);
  if (f.row < 0 || f.column < 0 || scan.rows == 0 || first < 0 || count < 0 ||
      first + count > scan.cols)
    throw std::logic_error("readE57Columns: columns outside the indexed scan");
  const ColourKind kind = f.rgb()            ? ColourKind::rgb
                          : f.intensity >= 0 ? ColourKind::intensity
                                             : ColourKind::none;
  return gridOf(readReturns(path, scan, f, first, count), scan.rows, count, kind);
}

}  // namespace rangefuse::io
