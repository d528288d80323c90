#include "PlyFile.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>  // splitWords

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Limits.h"

namespace rangefuse::io::internal {
namespace {

bool parseType(const std::string& s, PlyType& t) {
  static const std::map<std::string, PlyType> kTypes = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  auto it = kTypes.find(s);
  if (it == kTypes.end()) return false;
  t = it->second;
  return true;
}

std::vector<std::string> splitWords(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

}  // namespace

size_t typeSize(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 1;
}

PlyHeader parsePlyHeader(const std::string& path, std::string_view text) {
  PlyHeader h;
  size_t pos = 0;
  bool sawFormat = false;
  auto fail = [&](const std::string& msg) {
    throw InputError(path + ": line " + std::to_string(h.lines) + ": " + msg);
  };
  while (true) {
    if (pos >= text.size()) fail("header ends before end_header");
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string line(text.substr(pos, eol - pos));
    pos = std::min(eol + 1, text.size());
    ++h.lines;
    std::replace(line.begin(), line.end(), '\r', ' ');
    auto w = splitWords(line);
    if (h.lines == 1) {
      if (w.size() != 1 || w[0] != "ply") fail("not a PLY file (first line is not 'ply')");
      continue;
    }
    if (w.empty() || w[0] == "comment") continue;
    if (w[0] == "obj_info") {
      if (w.size() >= 3) h.objInfo[w[1]] = w[2];
    } else if (w[0] == "format") {
      if (w.size() != 3) fail("malformed format line");
      if (w[1] == "ascii")
        h.format = PlyFormat::Ascii;
      else if (w[1] == "binary_little_endian")
        h.format = PlyFormat::BinaryLittleEndian;
      else if (w[1] == "binary_big_endian")
        h.format = PlyFormat::BinaryBigEndian;
      else
        fail("unknown format '" + w[1] + "'");
      sawFormat = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) fail("malformed element line");
      PlyElement e;
      e.name = w[1];
      auto [p, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
      if (ec != std::errc() || p != w[2].data() + w[2].size())
        fail("bad element count '" + w[2] + "'");
      h.elements.push_back(e);
    } else if (w[0] == "property") {
      if (h.elements.empty()) fail("property before any element");
      PlyProperty prop;
      bool ok = false;
      if (w.size() == 5 && w[1] == "list") {
        prop.isList = true;
        prop.name = w[4];
        ok = parseType(w[2], prop.countType) && parseType(w[3], prop.type);
      } else if (w.size() == 3) {
        prop.name = w[2];
        ok = parseType(w[1], prop.type);
      }
      if (!ok) fail("malformed property line '" + line + "'");
      h.elements.back().properties.push_back(prop);
    } else if (w[0] == "end_header") {
      break;
    } else {
      fail("unknown header keyword '" + w[0] + "'");
    }
  }
  if (!sawFormat) throw InputError(path + ": header has no format line");
  h.bodyOffset = pos;
  return h;
}

namespace {

/// Reads values from an ASCII body one line (= one element item) at a time.
class AsciiCursor {
 public:
  AsciiCursor(const std::string& path, std::string_view text, size_t pos, int line)
      : path_(path), text_(text), pos_(pos), line_(line) {}

  /// Moves to the next non-empty line; false at end of file.
  bool nextLine() {
    while (pos_ < text_.size()) {
      size_t eol = text_.find('\n', pos_);
      if (eol == std::string::npos) eol = text_.size();
      cur_ = pos_;
      end_ = eol;
      pos_ = std::min(eol + 1, text_.size());
      ++line_;
      skipSpace();
      if (cur_ < end_) return true;
    }
    return false;
  }

  double next(const std::string& what) {
    skipSpace();
    if (cur_ >= end_) fail("too few values (expected " + what + ")");
    const char* b = text_.data() + cur_;
    const char* e = text_.data() + end_;
    double v = 0;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || (p < e && !isSpace(*p))) {
      const char* q = b;
      while (q < e && !isSpace(*q)) ++q;
      fail("cannot read '" + std::string(b, q) + "' as " + what);
    }
    cur_ = p - text_.data();
    return v;
  }

  void expectLineEnd() {
    skipSpace();
    if (cur_ < end_) fail("extra values at end of line");
  }

  [[noreturn]] void fail(const std::string& msg) const {
    throw InputError(path_ + ": line " + std::to_string(line_) + ": " + msg);
  }
  int line() const { return line_; }

 private:
  static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }
  void skipSpace() {
    while (cur_ < end_ && isSpace(text_[cur_])) ++cur_;
  }
  const std::string& path_;
  std::string_view text_;
  size_t pos_, cur_ = 0, end_ = 0;
  int line_;
};

/// Reads values from a binary body.
class BinaryCursor {
 public:
  BinaryCursor(std::string_view text, size_t pos, bool bigEndian)
      : text_(text), pos_(pos), swap_(bigEndian) {}

  size_t position() const { return pos_; }
  void skip(size_t n) { pos_ += n; }

  bool read(PlyType t, double& out) {
    size_t n = typeSize(t);
    if (pos_ + n > text_.size()) return false;
    unsigned char b[8];
    std::memcpy(b, text_.data() + pos_, n);
    if (swap_) std::reverse(b, b + n);
    pos_ += n;
    out = decode(t, b);
    return true;
  }
  size_t remaining() const { return text_.size() - pos_; }

 private:
  template <class T>
  static double as(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof(T));
    return static_cast<double>(v);
  }
  static double decode(PlyType t, const unsigned char* b) {
    switch (t) {
      case PlyType::Int8:
        return as<int8_t>(b);
      case PlyType::UInt8:
        return as<uint8_t>(b);
      case PlyType::Int16:
        return as<int16_t>(b);
      case PlyType::UInt16:
        return as<uint16_t>(b);
      case PlyType::Int32:
        return as<int32_t>(b);
      case PlyType::UInt32:
        return as<uint32_t>(b);
      case PlyType::Float32:
        return as<float>(b);
      case PlyType::Float64:
        return as<double>(b);
    }
    return 0;
  }
  std::string_view text_;
  size_t pos_;
  bool swap_;
};

PlyElementData makeData(const PlyElement& e) {
  PlyElementData d;
  d.element = e;
  for (const auto& p : e.properties) {
    if (p.isList) {
      d.listNames.push_back(p.name);
      d.listOffsets.emplace_back(1, 0);
      d.listValues.emplace_back();
    } else {
      d.scalarNames.push_back(p.name);
    }
  }
  return d;
}

/// Smallest body size an item can take, to refuse absurd counts before allocating.
size_t minItemBytes(const PlyElement& e, bool ascii) {
  size_t n = 0;
  for (const auto& p : e.properties) n += ascii ? 2 : typeSize(p.isList ? p.countType : p.type);
  return std::max<size_t>(n, 1);
}

constexpr double kMaxListLength = 255;

template <class Cursor, class ReadValue, class Fail>
void readItem(PlyElementData& d, Cursor&, ReadValue&& readValue, Fail&& fail) {
  size_t listIdx = 0;
  for (const auto& p : d.element.properties) {
    double v = readValue(p.isList ? p.countType : p.type, p.name);
    if (!p.isList) {
      d.scalars.push_back(v);
      continue;
    }
    if (v < 0 || v > kMaxListLength || v != std::floor(v))
      fail("bad list length " + std::to_string(v) + " for '" + p.name + "'");
    for (int i = 0; i < static_cast<int>(v); ++i) {
      const double item = readValue(p.type, p.name);
      // List items are indices: past 2^53 a double no longer holds every integer.
      if (!(std::abs(item) < 9007199254740992.0))
        fail("list item " + formatNumber(item) + " of '" + p.name + "' is out of range");
      d.listValues[listIdx].push_back(static_cast<int64_t>(item));
    }
    d.listOffsets[listIdx].push_back(static_cast<uint32_t>(d.listValues[listIdx].size()));
    ++listIdx;
  }
}

void reserveFor(PlyElementData& d) {
  d.scalars.reserve(d.element.count * d.scalarNames.size());
  for (auto& o : d.listOffsets) o.reserve(d.element.count + 1);
}

void readAsciiBody(PlyFile& f, const PlyHeader& h, std::string_view text) {
  AsciiCursor cur(f.path, text, h.bodyOffset, h.lines);
  for (const auto& e : h.elements) {
    PlyElementData d = makeData(e);
    reserveFor(d);
    for (uint64_t i = 0; i < e.count; ++i) {
      if (!cur.nextLine())
        throw InputError(f.path + ": truncated: file ends after " + std::to_string(i) + " of " +
                         std::to_string(e.count) + " '" + e.name + "' lines");
      auto fail = [&](const std::string& m) {
        cur.fail("element '" + e.name + "' #" + std::to_string(i) + ": " + m);
      };
      readItem(
          d, cur,
          [&](PlyType, const std::string& name) { return cur.next("property '" + name + "'"); },
          fail);
      cur.expectLineEnd();
    }
    f.elements.push_back(std::move(d));
  }
  if (cur.nextLine()) cur.fail("data after the last element: header counts do not match the body");
}

template <class T>
void decodeColumn(const char* first, size_t stride, uint64_t count, double* out, size_t columns) {
  for (uint64_t i = 0; i < count; ++i, first += stride) {
    T v;
    std::memcpy(&v, first, sizeof(T));
    out[i * columns] = static_cast<double>(v);
  }
}

/// An element of fixed-size scalars in host (little-endian) order, decoded a column at a time
/// rather than a value at a time. False, with nothing read, if the body is too short.
bool readScalarTable(PlyElementData& d, BinaryCursor& cur, std::string_view text) {
  const auto& props = d.element.properties;
  size_t stride = 0;
  for (const auto& p : props) stride += typeSize(p.type);
  const uint64_t count = d.element.count;
  if (stride == 0 || cur.remaining() / stride < count) return false;
  d.scalars.resize(count * props.size());
  const char* row = text.data() + cur.position();
  for (size_t c = 0, offset = 0; c < props.size(); offset += typeSize(props[c].type), ++c) {
    double* out = d.scalars.data() + c;
    const char* first = row + offset;
    switch (props[c].type) {
      case PlyType::Int8:
        decodeColumn<int8_t>(first, stride, count, out, props.size());
        break;
      case PlyType::UInt8:
        decodeColumn<uint8_t>(first, stride, count, out, props.size());
        break;
      case PlyType::Int16:
        decodeColumn<int16_t>(first, stride, count, out, props.size());
        break;
      case PlyType::UInt16:
        decodeColumn<uint16_t>(first, stride, count, out, props.size());
        break;
      case PlyType::Int32:
        decodeColumn<int32_t>(first, stride, count, out, props.size());
        break;
      case PlyType::UInt32:
        decodeColumn<uint32_t>(first, stride, count, out, props.size());
        break;
      case PlyType::Float32:
        decodeColumn<float>(first, stride, count, out, props.size());
        break;
      case PlyType::Float64:
        decodeColumn<double>(first, stride, count, out, props.size());
        break;
    }
  }
  cur.skip(count * stride);
  return true;
}

/// An element of one list with uchar counts and 32-bit integer items (range grids, faces),
/// little-endian. False, with nothing read, if the body ends early.
bool readIndexLists(PlyElementData& d, BinaryCursor& cur, std::string_view text) {
  const PlyProperty& p = d.element.properties[0];
  const bool isSigned = p.type == PlyType::Int32;
  const unsigned char* at = reinterpret_cast<const unsigned char*>(text.data()) + cur.position();
  const unsigned char* end = at + cur.remaining();
  std::vector<uint32_t>& offsets = d.listOffsets[0];
  std::vector<int64_t>& values = d.listValues[0];
  values.reserve(std::min<uint64_t>(d.element.count, cur.remaining() / 4));
  auto giveUp = [&] {
    offsets.resize(1);
    values.clear();
    return false;
  };
  for (uint64_t i = 0; i < d.element.count; ++i) {
    if (at == end) return giveUp();
    const unsigned n = *at++;
    if (static_cast<size_t>(end - at) < 4 * n) return giveUp();
    for (unsigned k = 0; k < n; ++k, at += 4) {
      int32_t s;
      uint32_t u;
      std::memcpy(&s, at, 4);
      std::memcpy(&u, at, 4);
      values.push_back(isSigned ? static_cast<int64_t>(s) : static_cast<int64_t>(u));
    }
    offsets.push_back(static_cast<uint32_t>(values.size()));
  }
  cur.skip(at - (reinterpret_cast<const unsigned char*>(text.data()) + cur.position()));
  return true;
}

/// The common layouts read in bulk; false leaves the element to the value-by-value reader
/// (which also words the errors of a short body).
bool readElementFast(PlyElementData& d, BinaryCursor& cur, std::string_view text, bool bigEndian) {
  const auto& props = d.element.properties;
  const uint16_t one = 1;
  const bool littleHost = *reinterpret_cast<const unsigned char*>(&one) == 1;
  if (bigEndian || !littleHost || props.empty()) return false;
  const bool scalars = std::none_of(props.begin(), props.end(), [](auto& p) { return p.isList; });
  if (scalars) return readScalarTable(d, cur, text);
  const bool indexList = props.size() == 1 && props[0].countType == PlyType::UInt8 &&
                         (props[0].type == PlyType::Int32 || props[0].type == PlyType::UInt32);
  return indexList && readIndexLists(d, cur, text);
}

void readBinaryBody(PlyFile& f, const PlyHeader& h, std::string_view text) {
  const bool bigEndian = h.format == PlyFormat::BinaryBigEndian;
  BinaryCursor cur(text, h.bodyOffset, bigEndian);
  for (const auto& e : h.elements) {
    PlyElementData d = makeData(e);
    reserveFor(d);
    if (readElementFast(d, cur, text, bigEndian)) {
      f.elements.push_back(std::move(d));
      continue;
    }
    for (uint64_t i = 0; i < e.count; ++i) {
      auto fail = [&](const std::string& m) {
        throw InputError(f.path + ": element '" + e.name + "' #" + std::to_string(i) + ": " + m);
      };
      auto readValue = [&](PlyType t, const std::string& name) {
        double v = 0;
        if (!cur.read(t, v))
          fail("truncated: file ends in property '" + name + "' (header says " +
               std::to_string(e.count) + " items)");
        return v;
      };
      readItem(d, cur, readValue, fail);
    }
    f.elements.push_back(std::move(d));
  }
  if (cur.remaining() != 0)
    throw InputError(f.path + ": " + std::to_string(cur.remaining()) +
                     " bytes after the last element: header counts do not match the body");
}

}  // namespace

int PlyElementData::scalarColumn(const std::string& name) const {
  auto it = std::find(scalarNames.begin(), scalarNames.end(), name);
  return it == scalarNames.end() ? -1 : static_cast<int>(it - scalarNames.begin());
}

int PlyElementData::listIndex(const std::string& name) const {
  auto it = std::find(listNames.begin(), listNames.end(), name);
  return it == listNames.end() ? -1 : static_cast<int>(it - listNames.begin());
}

const PlyElementData* PlyFile::find(const std::string& name) const {
  for (const auto& e : elements)
    if (e.element.name == name) return &e;
  return nullptr;
}

void checkPlyCounts(const std::string& path, const PlyHeader& h, size_t bytes,
                    uint64_t maxElements) {
  const bool ascii = h.format == PlyFormat::Ascii;
  const size_t body = bytes - h.bodyOffset;
  for (const auto& e : h.elements) {
    checkLimit(path, "element '" + e.name + "' count", static_cast<double>(e.count), maxElements,
               "max-elements");
    if (e.count > body / minItemBytes(e, ascii) + 1)
      throw InputError(path + ": element '" + e.name + "' claims " + std::to_string(e.count) +
                       " items but the body has only " + std::to_string(body) +
                       " bytes: header counts do not match the body");
  }
}

PlyFile parsePly(const std::string& path, std::string_view text, uint64_t maxElements) {
  const PlyHeader h = parsePlyHeader(path, text);
  checkPlyCounts(path, h, text.size(), maxElements);
  PlyFile f;
  f.path = path;
  f.format = h.format;
  f.objInfo = h.objInfo;
  if (h.format == PlyFormat::Ascii)
    readAsciiBody(f, h, text);
  else
    readBinaryBody(f, h, text);
  return f;
}

FileBytes::FileBytes(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(path + ": cannot open file");
  struct stat st;
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(path + ": is not a regular file");
  }
  // One allocation, left unset, and large reads: the file is copied once, straight into it.
  size_ = static_cast<size_t>(st.st_size);
  bytes_.reset(new char[std::max<size_t>(size_, 1)]);
  size_t got = 0;
  while (got < size_) {
    const ssize_t n = ::read(fd, bytes_.get() + got, std::min<size_t>(size_ - got, 1 << 30));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = n < 0 ? std::strerror(errno) : "the file shrank while being read";
      ::close(fd);
      throw InputError(path + ": read failed (" + why + ")");
    }
    got += static_cast<size_t>(n);
  }
  ::close(fd);
}

PlyFile readPly(const std::string& path, uint64_t maxElements) {
  const FileBytes bytes(path);
  return parsePly(path, bytes.view(), maxElements);
}

}  // namespace rangefuse::io::internal
