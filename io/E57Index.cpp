// The E57 header and XML tree: where each scan's points lie and what their records hold.
#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "E57Pages.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/E57.h"

namespace rangefuse::io {

using internal::E57Pages;
namespace pt = boost::property_tree;

int E57Field::bits() const {
  if (kind == Kind::single) return 32;
  if (kind == Kind::double_) return 64;
  const uint64_t range = static_cast<uint64_t>(maximum) - static_cast<uint64_t>(minimum);
  int bits = 0;
  while (bits < 64 && (range >> bits) != 0) ++bits;
  return bits;
}

namespace {

/// Reports what is wrong with the XML tree, naming the file and the element.
[[noreturn]] void bad(const std::string& path, const std::string& where, const std::string& what) {
  throw InputError(path + ": XML " + where + ": " + what);
}

std::string attribute(const pt::ptree& node, const std::string& name,
                      const std::string& otherwise = "") {
  const auto attrs = node.get_child_optional("<xmlattr>");
  if (!attrs) return otherwise;
  return attrs->get<std::string>(name, otherwise);
}

std::string text(const pt::ptree& node) {
  std::string s = node.data();
  const size_t a = s.find_first_not_of(" \t\r\n"), b = s.find_last_not_of(" \t\r\n");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

/// A number written as text; E57 writes zero as an empty element.
template <typename T>
T number(const std::string& s, const std::string& path, const std::string& where) {
  if (s.empty()) return T(0);
  std::istringstream in(s);
  T v{};
  std::string rest;
  if (!(in >> v) || (in >> rest)) bad(path, where, "'" + s + "' is not a number");
  if constexpr (std::is_floating_point_v<T>)
    if (!std::isfinite(v)) bad(path, where, "'" + s + "' is not finite");
  return v;
}

/// A child element's number, or `otherwise` when the element is absent.
double childNumber(const pt::ptree& node, const std::string& name, double otherwise,
                   const std::string& path, const std::string& where) {
  const auto child = node.get_child_optional(name);
  return child ? number<double>(text(*child), path, where + "/" + name) : otherwise;
}

Pose readPose(const pt::ptree& scan, const std::string& path, const std::string& where) {
  Pose pose{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()};
  const auto node = scan.get_child_optional("pose");
  if (!node) return pose;
  if (const auto r = node->get_child_optional("rotation")) {
    const std::string at = where + "/pose/rotation";
    const Eigen::Quaterniond q(childNumber(*r, "w", 1, path, at), childNumber(*r, "x", 0, path, at),
                               childNumber(*r, "y", 0, path, at),
                               childNumber(*r, "z", 0, path, at));
    if (!(q.norm() > 0.5 && q.norm() < 2)) bad(path, at, "not a unit quaternion");
    pose.R = q.normalized().toRotationMatrix();
  }
  if (const auto t = node->get_child_optional("translation")) {
    const std::string at = where + "/pose/translation";
    pose.t = {childNumber(*t, "x", 0, path, at), childNumber(*t, "y", 0, path, at),
              childNumber(*t, "z", 0, path, at)};
  }
  return pose;
}

E57Field readField(const std::string& name, const pt::ptree& node, const std::string& path,
                   const std::string& where) {
  E57Field f;
  f.name = name;
  const std::string type = attribute(node, "type");
  auto integerAttribute = [&](const char* key, int64_t otherwise) {
    const std::string s = attribute(node, key);
    return s.empty() ? otherwise : number<int64_t>(s, path, where + "@" + key);
  };
  if (type == "Float") {
    const std::string precision = attribute(node, "precision", "double");
    if (precision != "single" && precision != "double")
      bad(path, where, "precision '" + precision + "' is neither single nor double");
    f.kind = precision == "single" ? E57Field::Kind::single : E57Field::Kind::double_;
    return f;
  }
  if (type != "Integer" && type != "ScaledInteger")
    bad(path, where, "a point field of type '" + type + "' (Integer, ScaledInteger or Float)");
  f.kind = type == "Integer" ? E57Field::Kind::integer : E57Field::Kind::scaledInteger;
  f.minimum = integerAttribute("minimum", std::numeric_limits<int64_t>::min());
  f.maximum = integerAttribute("maximum", std::numeric_limits<int64_t>::max());
  if (f.maximum < f.minimum) bad(path, where, "maximum below minimum");
  if (f.kind == E57Field::Kind::scaledInteger) {
    const std::string scale = attribute(node, "scale"), offset = attribute(node, "offset");
    f.scale = scale.empty() ? 1.0 : number<double>(scale, path, where + "@scale");
    f.offset = offset.empty() ? 0.0 : number<double>(offset, path, where + "@offset");
    if (f.scale == 0) bad(path, where, "scale 0");
  }
  return f;
}

/// The prototype's terminal fields depth-first: one byte stream each, in this order.
void readPrototype(const pt::ptree& node, const std::string& prefix, std::vector<E57Field>& out,
                   const std::string& path, const std::string& where) {
  for (const auto& [name, child] : node) {
    if (name == "<xmlattr>" || name == "<xmlcomment>") continue;
    const std::string at = where + "/" + name;
    if (attribute(child, "type") == "Structure")
      readPrototype(child, prefix + name + ".", out, path, at);
    else
      out.push_back(readField(prefix + name, child, path, at));
  }
}

const E57Field* findField(const E57Scan& s, const std::string& name) {
  for (const E57Field& f : s.fields)
    if (f.name == name) return &f;
  return nullptr;
}

/// The scan's rows and columns from its indices' bounds (indexBounds when given).
void readGridShape(const pt::ptree& scan, E57Scan& s, const InputLimits& limits,
                   const std::string& path, const std::string& where) {
  const E57Field *row = findField(s, "rowIndex"), *col = findField(s, "columnIndex");
  if (!row || !col) return;
  int64_t r0 = row->minimum, r1 = row->maximum, c0 = col->minimum, c1 = col->maximum;
  if (const auto b = scan.get_child_optional("indexBounds")) {
    const std::string at = where + "/indexBounds";
    r0 = static_cast<int64_t>(childNumber(*b, "rowMinimum", double(r0), path, at));
    r1 = static_cast<int64_t>(childNumber(*b, "rowMaximum", double(r1), path, at));
    c0 = static_cast<int64_t>(childNumber(*b, "columnMinimum", double(c0), path, at));
    c1 = static_cast<int64_t>(childNumber(*b, "columnMaximum", double(c1), path, at));
  }
  if (r1 < r0 || c1 < c0) bad(path, where, "index bounds are empty");
  const double rows = double(r1) - double(r0) + 1, cols = double(c1) - double(c0) + 1;
  checkLimit(path + ": " + s.name, "grid cells", rows * cols, limits.maxGridCells,
             "max-grid-cells");
  s.rows = static_cast<int>(rows), s.cols = static_cast<int>(cols);
  s.firstRow = r0, s.firstColumn = c0;
}

/// Intensity and colour limits: the scan's own when given, else the fields' bounds.
void readLimits(const pt::ptree& scan, E57Scan& s, const std::string& path,
                const std::string& where) {
  auto bounds = [&](const E57Field* f, double& lo, double& hi) {
    if (!f || f->kind == E57Field::Kind::single || f->kind == E57Field::Kind::double_) return;
    lo = double(f->minimum) * f->scale + f->offset;
    hi = double(f->maximum) * f->scale + f->offset;
  };
  bounds(findField(s, "intensity"), s.intensityMin, s.intensityMax);
  bounds(findField(s, "colorRed"), s.colourMin, s.colourMax);
  if (const auto l = scan.get_child_optional("intensityLimits")) {
    s.intensityMin = childNumber(*l, "intensityMinimum", s.intensityMin, path, where);
    s.intensityMax = childNumber(*l, "intensityMaximum", s.intensityMax, path, where);
  }
  if (const auto l = scan.get_child_optional("colorLimits")) {
    s.colourMin = childNumber(*l, "colorRedMinimum", s.colourMin, path, where);
    s.colourMax = childNumber(*l, "colorRedMaximum", s.colourMax, path, where);
  }
  if (!(s.intensityMax > s.intensityMin)) s.intensityMin = 0, s.intensityMax = 1;
  if (!(s.colourMax > s.colourMin)) s.colourMin = 0, s.colourMax = 255;
}

E57Scan readScan(const pt::ptree& node, size_t k, uint64_t fileSize, const InputLimits& limits,
                 const std::string& path) {
  E57Scan s;
  const std::string where = "data3D scan " + std::to_string(k + 1);
  if (const auto n = node.get_child_optional("name")) s.name = text(*n);
  if (const auto g = node.get_child_optional("guid")) s.guid = text(*g);
  s.pose = readPose(node, path, where);
  const auto points = node.get_child_optional("points");
  if (!points) bad(path, where, "no points");
  if (attribute(*points, "type") != "CompressedVector")
    bad(path, where + "/points", "type '" + attribute(*points, "type") + "', not CompressedVector");
  s.section =
      number<uint64_t>(attribute(*points, "fileOffset"), path, where + "/points@fileOffset");
  s.records =
      number<uint64_t>(attribute(*points, "recordCount"), path, where + "/points@recordCount");
  if (s.section < 48 || s.section >= fileSize)
    bad(path, where + "/points", "fileOffset " + std::to_string(s.section) + " outside the file");
  checkLimit(path + ": " + where, "point records", double(s.records), limits.maxElements,
             "max-elements");
  const auto prototype = points->get_child_optional("prototype");
  if (!prototype) bad(path, where + "/points", "no prototype");
  readPrototype(*prototype, "", s.fields, path, where + "/points/prototype");
  if (const auto codecs = points->get_child_optional("codecs"))
    for (const auto& [name, codec] : *codecs)
      if (name != "<xmlattr>" && name != "<xmlcomment>")
        bad(path, where + "/points/codecs",
            "a codec other than the bit-pack codec ('" + name +
                "'); only bit-packed records are read");
  const bool cartesian =
      findField(s, "cartesianX") && findField(s, "cartesianY") && findField(s, "cartesianZ");
  s.spherical = !cartesian && findField(s, "sphericalRange") && findField(s, "sphericalAzimuth") &&
                findField(s, "sphericalElevation");
  if (!cartesian && !s.spherical)
    bad(path, where + "/points/prototype",
        "no coordinates (cartesianX/Y/Z or sphericalRange/Azimuth/Elevation)");
  readGridShape(node, s, limits, path, where);
  readLimits(node, s, path, where);
  if (s.name.empty()) s.name = "scan " + std::to_string(k + 1);
  return s;
}

uint32_t le32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

uint64_t le64(const uint8_t* p) {
  return uint64_t(le32(p)) | uint64_t(le32(p + 4)) << 32;
}

/// The XML text, after the header is checked.
std::string readXml(E57Pages& pages, const InputLimits& limits) {
  const std::string& path = pages.path();
  uint8_t h[48];
  pages.read(0, h, 48);
  if (std::memcmp(h, "ASTM-E57", 8) != 0) throw InputError(path + ": not an E57 file (signature)");
  const uint32_t major = le32(h + 8), minor = le32(h + 12);
  const uint64_t length = le64(h + 16), xmlAt = le64(h + 24), xmlLength = le64(h + 32),
                 page = le64(h + 40);
  if (major != 1)
    throw InputError(path + ": E57 version " + std::to_string(major) + "." + std::to_string(minor) +
                     ": version 1 is read");
  if (page != internal::kE57Page)
    throw InputError(path + ": page size " + std::to_string(page) + ", not 1024");
  if (length != pages.physicalSize())
    throw InputError(path + ": the header says " + std::to_string(length) +
                     " bytes, the file has " + std::to_string(pages.physicalSize()) +
                     " (truncated or damaged)");
  checkLimit(path, "XML bytes", double(xmlLength), limits.maxElements, "max-elements");
  const uint64_t from = internal::e57Logical(xmlAt);
  if (xmlAt < 48 || xmlLength == 0 || from + xmlLength > pages.logicalSize())
    throw InputError(path + ": the XML section (byte " + std::to_string(xmlAt) + ", " +
                     std::to_string(xmlLength) + " bytes) lies outside the file");
  std::string xml(xmlLength, '\0');
  pages.read(from, xml.data(), xml.size());
  return xml;
}

}  // namespace

std::vector<E57Scan> indexE57(const std::string& path, const InputLimits& limits) {
  E57Pages pages(path);
  std::istringstream in(readXml(pages, limits));
  pt::ptree tree;
  try {
    pt::read_xml(in, tree);
  } catch (const pt::xml_parser_error& e) {
    throw InputError(path + ": XML: line " + std::to_string(e.line()) + ": " + e.message());
  }
  const auto root = tree.get_child_optional("e57Root");
  if (!root) bad(path, "root", "no e57Root element");
  std::vector<E57Scan> scans;
  if (const auto data3D = root->get_child_optional("data3D"))
    for (const auto& [name, child] : *data3D)
      if (name != "<xmlattr>" && name != "<xmlcomment>")
        scans.push_back(readScan(child, scans.size(), pages.physicalSize(), limits, path));
  if (scans.empty()) throw InputError(path + ": no scan in the file (data3D is empty)");
  return scans;
}

}  // namespace rangefuse::io
