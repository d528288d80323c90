// Writing stations as an E57 file (for tests and synthetic data): every scan's records packed
// into data packets by the bit-pack codec, an index packet after them, the XML last, and the
// whole laid out on checksummed pages.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "E57Pages.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/E57.h"

namespace rangefuse::io {

using internal::e57Physical;

namespace {

/// One field's values, packed least significant bit first.
struct PackedField {
  explicit PackedField(E57Field f) : field(std::move(f)) {}

  E57Field field;
  std::vector<uint8_t> bytes;
  uint64_t bitCount = 0;

  void put(double value) {
    using Kind = E57Field::Kind;
    if (field.kind == Kind::single || field.kind == Kind::double_) {
      uint8_t b[8];
      if (field.kind == Kind::single) {
        const float f = static_cast<float>(value);
        std::memcpy(b, &f, 4);
      } else {
        std::memcpy(b, &value, 8);
      }
      bytes.insert(bytes.end(), b, b + field.bits() / 8);
      bitCount += static_cast<uint64_t>(field.bits());
      return;
    }
    const double raw = field.kind == Kind::scaledInteger
                           ? std::round((value - field.offset) / field.scale)
                           : std::round(value);
    const auto v =
        static_cast<int64_t>(std::clamp(raw, double(field.minimum), double(field.maximum)));
    const uint64_t u = static_cast<uint64_t>(v) - static_cast<uint64_t>(field.minimum);
    for (int k = 0; k < field.bits(); ++k, ++bitCount) {
      if (bitCount % 8 == 0) bytes.push_back(0);
      bytes.back() = static_cast<uint8_t>(bytes.back() | ((u >> k) & 1) << (bitCount % 8));
    }
  }
};

E57Field integerField(const std::string& name, int64_t lo, int64_t hi) {
  E57Field f;
  f.name = name, f.kind = E57Field::Kind::integer, f.minimum = lo, f.maximum = hi;
  return f;
}

E57Field coordinateField(const std::string& name, const E57Writing& how, double bound) {
  E57Field f;
  f.name = name;
  switch (how.coordinates) {
    case E57Coordinates::cartesianSingle:
      f.kind = E57Field::Kind::single;
      break;
    case E57Coordinates::cartesianScaled: {
      f.kind = E57Field::Kind::scaledInteger, f.scale = how.scaledStep;
      const auto steps = static_cast<int64_t>(std::ceil(bound / how.scaledStep)) + 1;
      f.minimum = -steps, f.maximum = steps;
      break;
    }
    default:
      f.kind = E57Field::Kind::double_;
  }
  return f;
}

/// The prototype of a station's records.
std::vector<PackedField> prototype(const RangeGrid& g, const E57Writing& how) {
  double bound = 1;
  for (const Eigen::Vector3d& p : g.points) bound = std::max(bound, p.cwiseAbs().maxCoeff());
  const bool spherical = how.coordinates == E57Coordinates::sphericalDouble;
  std::vector<PackedField> out;
  for (const char* n : {"X", "Y", "Z"})
    out.emplace_back(spherical ? E57Field{}
                               : coordinateField(std::string("cartesian") + n, how, bound));
  if (spherical) {
    const char* names[3] = {"sphericalRange", "sphericalAzimuth", "sphericalElevation"};
    for (int a = 0; a < 3; ++a)
      out[a].field.name = names[a], out[a].field.kind = E57Field::Kind::double_;
  }
  if (how.structured) {
    out.emplace_back(
        integerField(spherical ? "sphericalInvalidState" : "cartesianInvalidState", 0, 2));
    out.emplace_back(integerField("rowIndex", 0, g.rows - 1));
    out.emplace_back(integerField("columnIndex", 0, g.cols - 1));
  }
  if (g.colourKind == ColourKind::rgb) {
    for (const char* n : {"colorRed", "colorGreen", "colorBlue"})
      out.emplace_back(integerField(n, 0, 255));
  }
  if (g.colourKind != ColourKind::rgb || how.intensityToo) {
    E57Field f;
    f.name = "intensity", f.kind = E57Field::Kind::single;
    out.emplace_back(f);
  }
  return out;
}

/// Packs a station's records: every cell in column-major order when structured (empty ones
/// invalid, at the origin), else its points alone.
std::vector<PackedField> pack(const RangeGrid& g, const E57Writing& how, uint64_t& records) {
  std::vector<PackedField> fields = prototype(g, how);
  const bool spherical = how.coordinates == E57Coordinates::sphericalDouble;
  records = 0;
  for (int c = 0; c < g.cols; ++c)
    for (int r = 0; r < g.rows; ++r) {
      const int32_t k = g.at(r, c);
      if (k < 0 && !how.structured) continue;
      ++records;
      const Eigen::Vector3d p = k < 0 ? Eigen::Vector3d::Zero() : g.points[k];
      const Colour colour = k < 0 || g.colours.empty() ? Colour::Constant(0.5f) : g.colours[k];
      size_t i = 0;
      if (spherical) {
        fields[i++].put(p.norm());
        fields[i++].put(std::atan2(p.y(), p.x()));
        fields[i++].put(std::atan2(p.z(), p.head<2>().norm()));
      } else {
        for (int a = 0; a < 3; ++a) fields[i++].put(p[a]);
      }
      if (how.structured) {
        fields[i++].put(k < 0 ? 2 : 0);
        fields[i++].put(r);
        fields[i++].put(c);
      }
      const bool rgb = g.colourKind == ColourKind::rgb;
      if (rgb)
        for (int a = 0; a < 3; ++a) fields[i++].put(colourByte(colour[a]));
      if (!rgb || how.intensityToo) fields[i++].put(rgb ? colour.mean() : colour[0]);
    }
  return fields;
}

void put16(std::string& s, uint64_t v) {
  for (int k = 0; k < 2; ++k) s.push_back(static_cast<char>(v >> (8 * k) & 0xFF));
}

void put64(std::string& s, uint64_t v) {
  for (int k = 0; k < 8; ++k) s.push_back(static_cast<char>(v >> (8 * k) & 0xFF));
}

void align4(std::string& s) {
  while (s.size() % 4) s.push_back('\0');
}

/// Appends one scan's compressed vector section at the end of the logical bytes `file`:
/// data packets of at most `packetRecords` records' worth of each stream (or 64 KiB), then an
/// index packet naming them. Returns the section's logical offset.
uint64_t appendSection(std::string& file, const std::vector<PackedField>& fields, uint64_t records,
                       const E57Writing& how) {
  align4(file);
  const uint64_t at = file.size();
  std::string packets;
  // Packets share each stream's bytes evenly; their count keeps every packet under 64 KiB.
  uint64_t total = 0, bitsPerRecord = 0;
  for (const PackedField& f : fields) total += f.bytes.size(), bitsPerRecord += f.field.bits();
  uint64_t count = std::max<uint64_t>(1, (total + 6 + 2 * fields.size()) / 60000 + 1);
  if (how.packetRecords > 0)
    count = std::max(count, (records + how.packetRecords - 1) / how.packetRecords);
  std::vector<std::pair<uint64_t, uint64_t>> index;  // first record, physical offset
  std::vector<size_t> sent(fields.size(), 0);
  for (uint64_t k = 0; k < count; ++k) {
    std::string p;
    p.push_back(1), p.push_back(0);
    put16(p, 0);  // length, filled below
    put16(p, fields.size());
    std::vector<size_t> share(fields.size());
    for (size_t f = 0; f < fields.size(); ++f) {
      const size_t n = fields[f].bytes.size();
      share[f] = k + 1 == count ? n - sent[f] : std::min(n - sent[f], (n + count - 1) / count);
      put16(p, share[f]);
    }
    for (size_t f = 0; f < fields.size(); ++f) {
      p.append(reinterpret_cast<const char*>(fields[f].bytes.data()) + sent[f], share[f]);
      sent[f] += share[f];
    }
    align4(p);
    p[2] = static_cast<char>((p.size() - 1) & 0xFF), p[3] = static_cast<char>((p.size() - 1) >> 8);
    index.emplace_back(
        bitsPerRecord ? 8 * (sent[0] - share[0]) / std::max(1, fields[0].field.bits()) : 0,
        e57Physical(at + 32 + packets.size()));
    packets += p;
    // An empty packet between the first two data packets, as readers must skip them.
    if (k == 0 && count > 1) packets += std::string("\x02\x00\x03\x00", 4);
  }
  std::string idx;
  idx.push_back(0), idx.push_back(0);
  put16(idx, 0);
  put16(idx, index.size());
  idx.push_back(0);     // index level
  idx.append(9, '\0');  // reserved
  for (const auto& [record, offset] : index) put64(idx, record), put64(idx, offset);
  idx[2] = static_cast<char>((idx.size() - 1) & 0xFF),
  idx[3] = static_cast<char>((idx.size() - 1) >> 8);
  std::string head;
  head.push_back(1);
  head.append(7, '\0');
  put64(head, 32 + packets.size() + idx.size());
  put64(head, e57Physical(at + 32));
  put64(head, e57Physical(at + 32 + packets.size()));
  file += head + packets + idx;
  return at;
}

std::string fieldXml(const E57Field& f) {
  std::ostringstream x;
  x.precision(17);
  x << "<" << f.name;
  switch (f.kind) {
    case E57Field::Kind::single:
      x << " type=\"Float\" precision=\"single\"/>";
      break;
    case E57Field::Kind::double_:
      x << " type=\"Float\"/>";
      break;
    case E57Field::Kind::integer:
      x << " type=\"Integer\" minimum=\"" << f.minimum << "\" maximum=\"" << f.maximum << "\"/>";
      break;
    case E57Field::Kind::scaledInteger:
      x << " type=\"ScaledInteger\" minimum=\"" << f.minimum << "\" maximum=\"" << f.maximum
        << "\" scale=\"" << f.scale << "\" offset=\"" << f.offset << "\"/>";
  }
  return x.str();
}

std::string scanXml(size_t k, const RangeGrid& g, const Pose& pose,
                    const std::vector<PackedField>& fields, uint64_t records, uint64_t section,
                    const E57Writing& how) {
  std::ostringstream x;
  x.precision(17);
  const Eigen::Quaterniond q(pose.R);
  x << "<vectorChild type=\"Structure\">"
    << "<guid type=\"String\"><![CDATA[{rangefuse-station-" << k + 1 << "}]]></guid>"
    << "<name type=\"String\"><![CDATA[station " << k + 1 << "]]></name>"
    << "<pose type=\"Structure\"><rotation type=\"Structure\"><w type=\"Float\">" << q.w()
    << "</w><x type=\"Float\">" << q.x() << "</x><y type=\"Float\">" << q.y()
    << "</y><z type=\"Float\">" << q.z() << "</z></rotation><translation type=\"Structure\">"
    << "<x type=\"Float\">" << pose.t.x() << "</x><y type=\"Float\">" << pose.t.y()
    << "</y><z type=\"Float\">" << pose.t.z() << "</z></translation></pose>";
  if (how.structured)
    x << "<indexBounds type=\"Structure\"><rowMinimum type=\"Integer\">0</rowMinimum>"
      << "<rowMaximum type=\"Integer\">" << g.rows - 1 << "</rowMaximum>"
      << "<columnMinimum type=\"Integer\">0</columnMinimum><columnMaximum type=\"Integer\">"
      << g.cols - 1 << "</columnMaximum></indexBounds>";
  if (g.colourKind == ColourKind::rgb)
    x << "<colorLimits type=\"Structure\"><colorRedMinimum type=\"Integer\">0</colorRedMinimum>"
      << "<colorRedMaximum type=\"Integer\">255</colorRedMaximum></colorLimits>";
  if (g.colourKind != ColourKind::rgb || how.intensityToo)
    x << "<intensityLimits type=\"Structure\"><intensityMinimum type=\"Float\">0"
      << "</intensityMinimum><intensityMaximum type=\"Float\">1</intensityMaximum>"
      << "</intensityLimits>";
  x << "<points type=\"CompressedVector\" fileOffset=\"" << e57Physical(section)
    << "\" recordCount=\"" << records << "\"><prototype type=\"Structure\">";
  for (const PackedField& f : fields) x << fieldXml(f.field);
  x << "</prototype><codecs type=\"Vector\" allowHeterogeneousChildren=\"1\"/></points>"
    << "</vectorChild>";
  return x.str();
}

/// The logical bytes laid on pages: each 1020 followed by their CRC-32C, big-endian.
std::string paged(std::string logical) {
  logical.resize((logical.size() + internal::kE57PageData - 1) / internal::kE57PageData *
                 internal::kE57PageData);
  std::string out;
  out.reserve(logical.size() / internal::kE57PageData * internal::kE57Page);
  for (size_t at = 0; at < logical.size(); at += internal::kE57PageData) {
    out.append(logical, at, internal::kE57PageData);
    const uint32_t crc = internal::crc32c(reinterpret_cast<const uint8_t*>(logical.data()) + at,
                                          internal::kE57PageData);
    for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>(crc >> (8 * k) & 0xFF));
  }
  return out;
}

}  // namespace

void writeE57(const std::string& path, const std::vector<RangeGrid>& grids,
              const std::vector<Pose>& poses, const E57Writing& how) {
  std::string file(48, '\0');
  std::string scans;
  for (size_t k = 0; k < grids.size(); ++k) {
    uint64_t records = 0;
    const std::vector<PackedField> fields = pack(grids[k], how, records);
    const uint64_t section = appendSection(file, fields, records, how);
    scans += scanXml(k, grids[k], poses[k], fields, records, section, how);
  }
  const std::string xml =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<e57Root type=\"Structure\" xmlns=\"http://www.astm.org/COMMIT/E57/2010-e57-v1.0\">"
      "<formatName type=\"String\"><![CDATA[ASTM E57 3D Imaging Data File]]></formatName>"
      "<guid type=\"String\"><![CDATA[{rangefuse-file}]]></guid>"
      "<versionMajor type=\"Integer\">1</versionMajor><versionMinor type=\"Integer\">0"
      "</versionMinor><data3D type=\"Vector\" allowHeterogeneousChildren=\"1\">" +
      scans + "</data3D><images2D type=\"Vector\" allowHeterogeneousChildren=\"1\"/></e57Root>\n";
  align4(file);
  const uint64_t xmlAt = file.size();
  file += xml;
  const uint64_t pages = (file.size() + internal::kE57PageData - 1) / internal::kE57PageData;
  std::string head = "ASTM-E57";
  for (int k = 0; k < 4; ++k) head.push_back(k == 0 ? 1 : 0);  // major 1
  head.append(4, '\0');                                        // minor 0
  put64(head, pages * internal::kE57Page);
  put64(head, e57Physical(xmlAt));
  put64(head, xml.size());
  put64(head, internal::kE57Page);
  file.replace(0, 48, head);
  const std::string bytes = paged(std::move(file));
  writeAtomically(
      path, [&](std::ostream& out) { out.write(bytes.data(), std::streamsize(bytes.size())); });
}

}  // namespace rangefuse::io
