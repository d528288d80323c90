#include "rangefuse/io/Ptx.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <memory>
#include <stdexcept>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {
namespace {

/// Lines of a file read in large blocks, with the byte offset and number of each line.
class LineReader {
 public:
  /// Reads from byte `offset`, numbering lines from `line`, in blocks of `block` bytes (a short
  /// range needs no more than its own bytes).
  LineReader(const std::string& path, uint64_t offset, uint64_t line,
             size_t block = size_t{1} << 22)
      : path_(path),
        file_(std::fopen(path.c_str(), "rb"), &std::fclose),
        buffer_(std::max<size_t>(block, 64)),
        offset_(offset),
        line_(line - 1) {
    if (!file_) throw InputError(path + ": cannot open for reading");
    if (offset > 0 && fseeko(file_.get(), static_cast<off_t>(offset), SEEK_SET) != 0)
      throw InputError(path + ": cannot seek to byte " + std::to_string(offset));
  }

  /// The next line without its end (CR LF or LF); false at the end of the file.
  bool next(std::string_view& out) {
    for (;;) {
      const char* begin = buffer_.data() + at_;
      const void* nl = std::memchr(begin, '\n', end_ - at_);
      if (nl || (eof_ && at_ < end_)) {
        const size_t n = nl ? static_cast<const char*>(nl) - begin : end_ - at_;
        out = std::string_view(begin, n);
        if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
        const size_t used = nl ? n + 1 : n;
        at_ += used;
        offset_ += used;
        ++line_;
        return true;
      }
      if (eof_) return false;
      refill();
    }
  }

  /// Skips n lines, counting their ends only; false when the file ends first.
  bool skip(uint64_t n) {
    std::string_view unused;
    while (n > 0) {
      const char* begin = buffer_.data() + at_;
      const void* nl = std::memchr(begin, '\n', end_ - at_);
      if (!nl) {
        if (eof_) return at_ < end_ && n == 1 ? next(unused) : false;
        refill();
        continue;
      }
      const size_t used = static_cast<const char*>(nl) - begin + 1;
      at_ += used, offset_ += used, ++line_, --n;
    }
    return true;
  }

  uint64_t line() const { return line_; }      ///< number of the last line returned
  uint64_t offset() const { return offset_; }  ///< byte offset of the next line
  const std::string& path() const { return path_; }

 private:
  void refill() {
    std::memmove(buffer_.data(), buffer_.data() + at_, end_ - at_);
    end_ -= at_, at_ = 0;
    if (end_ == buffer_.size()) buffer_.resize(2 * buffer_.size());  // a very long line
    end_ += std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_.get());
    if (end_ < buffer_.size()) {
      if (std::ferror(file_.get())) throw InputError(path_ + ": read error");
      eof_ = true;
    }
  }

  std::string path_;
  std::unique_ptr<FILE, int (*)(FILE*)> file_;
  std::vector<char> buffer_;
  size_t at_ = 0, end_ = 0;
  bool eof_ = false;
  uint64_t offset_, line_;
};

[[noreturn]] void fail(const LineReader& in, const std::string& what) {
  throw InputError(in.path() + ":" + std::to_string(in.line()) + ": " + what);
}

/// The whitespace-separated numbers of a line (at most `most`); their count.
int parseNumbers(std::string_view text, double* out, int most, bool& bad) {
  int n = 0;
  bad = false;
  const char* p = text.data();
  const char* end = p + text.size();
  for (;;) {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (p == end) return n;
    if (n == most) return most + 1;
    const auto [next, ec] = std::from_chars(p, end, out[n]);
    if (ec != std::errc() || (next < end && *next != ' ' && *next != '\t')) {
      bad = true;
      return n;
    }
    p = next;
    ++n;
  }
}

/// The next line as exactly `count` numbers, else an error naming `what`.
void readNumbers(LineReader& in, double* out, int count, const char* what) {
  std::string_view line;
  if (!in.next(line)) fail(in, std::string("file ends before the ") + what);
  bool bad = false;
  if (parseNumbers(line, out, count, bad) != count || bad)
    fail(in, std::string("expected the ") + what + " (" + std::to_string(count) + " numbers)");
  for (int k = 0; k < count; ++k)
    if (!std::isfinite(out[k])) fail(in, std::string("non-finite number in the ") + what);
}

/// Reads one scan header; false at a clean end of the file.
bool readHeader(LineReader& in, PtxScan& scan, const InputLimits& limits) {
  std::string_view line;
  do {
    if (!in.next(line)) return false;
  } while (line.find_first_not_of(" \t") == std::string_view::npos);  // blank lines between
  double v[4];
  bool bad = false;
  if (parseNumbers(line, v, 1, bad) != 1 || bad || !(v[0] >= 1) || v[0] != std::floor(v[0]))
    fail(in, "expected the number of columns (a positive integer)");
  double rows;
  readNumbers(in, &rows, 1, "number of rows");
  if (!(rows >= 1) || rows != std::floor(rows))
    fail(in, "the number of rows must be a positive integer");
  checkLimit(in.path() + ":" + std::to_string(in.line()), "grid cells", v[0] * rows,
             limits.maxGridCells, "max-grid-cells");
  scan.cols = static_cast<int>(v[0]);
  scan.rows = static_cast<int>(rows);
  for (const char* what :
       {"scanner position", "scanner X axis", "scanner Y axis", "scanner Z axis"})
    readNumbers(in, v, 3, what);
  double m[4][4];
  for (int r = 0; r < 4; ++r) readNumbers(in, m[r], 4, "transform row");
  // world = [x y z 1] M: the rotation is the transpose of M's upper block.
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) scan.pose.R(c, r) = m[r][c];
  scan.pose.t = Eigen::Vector3d(m[3][0], m[3][1], m[3][2]);
  scan.offset = in.offset();
  scan.line = in.line() + 1;
  return true;
}

}  // namespace

std::vector<PtxScan> indexPtx(const std::string& path, const InputLimits& limits) {
  LineReader in(path, 0, 1);
  std::vector<PtxScan> scans;
  PtxScan scan;
  while (readHeader(in, scan, limits)) {
    // A station is placed by a rigid motion: a header that scales or shears would bend it.
    const std::string problem = rotationProblem(scan.pose.R);
    if (!problem.empty())
      throw InputError(path + ":" + std::to_string(scan.line - 1) + ": station " +
                       std::to_string(scans.size()) + ": the header's transform is " + problem);
    const uint64_t points = static_cast<uint64_t>(scan.cols) * static_cast<uint64_t>(scan.rows);
    scan.columns.reserve(scan.cols);
    for (int c = 0; c < scan.cols; ++c) {
      scan.columns.push_back(in.offset());
      if (!in.skip(scan.rows))
        throw InputError(path + ":" + std::to_string(scan.line) + ": scan " +
                         std::to_string(scans.size() + 1) + " has fewer than " +
                         std::to_string(points) + " point lines");
    }
    scan.end = in.offset();
    scans.push_back(scan);
    scan = PtxScan{};
  }
  if (scans.empty()) throw InputError(path + ": no scan in the file");
  return scans;
}

RangeGrid readPtxScan(const std::string& path, const PtxScan& scan) {
  return readPtxColumns(path, scan, 0, scan.cols);
}

namespace {

/// A point line's colour: r g b (0-255) when the line has them and `rgb`, else its intensity
/// as grey. Intensities in [0, 1] are taken as they are; others as the 12-bit signed range some
/// exporters write ([-2048, 2047]), clamped.
Colour ptxColour(const double* v, int n, bool rgb) {
  if (n == 7 && rgb)
    return Colour(static_cast<float>(std::clamp(v[4] / 255, 0.0, 1.0)),
                  static_cast<float>(std::clamp(v[5] / 255, 0.0, 1.0)),
                  static_cast<float>(std::clamp(v[6] / 255, 0.0, 1.0)));
  const double i = v[3] >= 0 && v[3] <= 1 ? v[3] : std::clamp((v[3] + 2048) / 4095, 0.0, 1.0);
  return Colour::Constant(static_cast<float>(i));
}

}  // namespace

RangeGrid readPtxColumns(const std::string& path, const PtxScan& scan, int first, int count) {
  if (first < 0 || count < 0 || first + count > scan.cols ||
      scan.columns.size() != static_cast<size_t>(scan.cols))
    throw std::logic_error("readPtxColumns: columns outside the indexed scan");
  RangeGrid grid;
  grid.cols = count;
  grid.rows = scan.rows;
  grid.spherical = true;
  grid.cell.assign(static_cast<size_t>(count) * scan.rows, -1);
  if (count == 0) return grid;
  const uint64_t from = scan.columns[first];
  const uint64_t to = first + count < scan.cols ? scan.columns[first + count] : scan.end;
  LineReader in(path, from, scan.line + static_cast<uint64_t>(first) * scan.rows,
                static_cast<size_t>(std::min<uint64_t>(to - from + 2, uint64_t{1} << 22)));
  std::string_view line;
  double v[7];
  for (int c = 0; c < count; ++c)
    for (int r = 0; r < scan.rows; ++r) {
      if (!in.next(line)) fail(in, "file ends inside the scan");
      bool bad = false;
      const int n = parseNumbers(line, v, 7, bad);
      if (bad || (n != 4 && n != 7)) fail(in, "expected 'x y z intensity [r g b]'");
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
        fail(in, "non-finite coordinate");
      if (v[0] == 0 && v[1] == 0 && v[2] == 0) continue;  // no return
      grid.cell[static_cast<size_t>(r) * count + c] = static_cast<int32_t>(grid.points.size());
      grid.points.emplace_back(v[0], v[1], v[2]);
      grid.colours.push_back(ptxColour(v, n, !scan.intensity));
      if (n == 7 && !scan.intensity) grid.colourKind = ColourKind::rgb;
    }
  if (grid.colourKind == ColourKind::none && !grid.points.empty())
    grid.colourKind = ColourKind::intensity;
  if (grid.points.empty()) grid.colours.clear();
  return grid;
}

void writePtx(const std::string& path, const std::vector<RangeGrid>& grids,
              const std::vector<Pose>& poses) {
  writeAtomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (size_t i = 0; i < grids.size(); ++i) {
      const RangeGrid& g = grids[i];
      const Pose& p = poses[i];
      out << g.cols << "\n" << g.rows << "\n";
      out << p.t.x() << " " << p.t.y() << " " << p.t.z() << "\n";
      for (int a = 0; a < 3; ++a) out << p.R(0, a) << " " << p.R(1, a) << " " << p.R(2, a) << "\n";
      for (int r = 0; r < 3; ++r)
        out << p.R(0, r) << " " << p.R(1, r) << " " << p.R(2, r) << " 0\n";
      out << p.t.x() << " " << p.t.y() << " " << p.t.z() << " 1\n";
      for (int c = 0; c < g.cols; ++c)
        for (int r = 0; r < g.rows; ++r) {
          const int32_t k = g.at(r, c);
          if (k < 0) {
            out << "0 0 0 0\n";
          } else {
            const Eigen::Vector3d& q = g.points[static_cast<size_t>(k)];
            out << q.x() << " " << q.y() << " " << q.z();
            const Colour c = g.colours.empty() ? Colour::Constant(0.5f) : g.colours[k];
            if (g.colourKind == ColourKind::rgb)
              out << " " << (c[0] + c[1] + c[2]) / 3 << " " << int(colourByte(c[0])) << " "
                  << int(colourByte(c[1])) << " " << int(colourByte(c[2])) << "\n";
            else
              out << " " << c[0] << "\n";
          }
        }
    }
  });
}

}  // namespace rangefuse::io
