// E57: round trips through our writer with every coordinate encoding and packet size, values
// spanning packets, a checksum error found on every page, truncation and malformed XML named.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <random>

#include "../../io/E57Pages.h"
#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/E57.h"
#include "rangefuse/io/ScanFiles.h"

using namespace rangefuse;
using test::TempDir;

namespace {

/// A station: points in every direction at ranges 1-5, a fifth of the cells empty, coloured
/// by intensity or (rgb) by bytes.
RangeGrid stationGrid(int cols, int rows, unsigned seed, bool rgb) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-5, 5);
  RangeGrid g;
  g.cols = cols, g.rows = rows, g.spherical = true;
  g.cell.assign(static_cast<size_t>(cols) * rows, -1);
  g.colourKind = rgb ? ColourKind::rgb : ColourKind::intensity;
  for (size_t k = 0; k < g.cell.size(); ++k) {
    if (rng() % 5 == 0) continue;
    g.cell[k] = static_cast<int32_t>(g.points.size());
    g.points.emplace_back(u(rng), u(rng), u(rng));
    if (rgb)
      g.colours.emplace_back(float(rng() % 256) / 255, float(rng() % 256) / 255,
                             float(rng() % 256) / 255);
    else
      g.colours.push_back(Colour::Constant(std::uniform_real_distribution<float>(0, 1)(rng)));
  }
  return g;
}

std::string wholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The message reading every scan of the file gives, or "" when it reads.
std::string message(const std::string& path) {
  try {
    for (const io::E57Scan& s : io::indexE57(path)) io::readE57Scan(path, s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// The file's logical bytes (checksums dropped), and the same laid on pages again.
std::string logical(const std::string& bytes) {
  std::string out;
  for (size_t at = 0; at < bytes.size(); at += 1024) out.append(bytes, at, 1020);
  return out;
}

std::string paged(const std::string& logical) {
  std::string out;
  for (size_t at = 0; at < logical.size(); at += 1020) {
    out.append(logical, at, 1020);
    const uint32_t crc =
        io::internal::crc32c(reinterpret_cast<const uint8_t*>(logical.data()) + at, 1020);
    for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>(crc >> (8 * k) & 0xFF));
  }
  return out;
}

void expectSameGrid(const RangeGrid& got, const RangeGrid& want, double tolerance) {
  ASSERT_EQ(got.rows, want.rows);
  ASSERT_EQ(got.cols, want.cols);
  EXPECT_TRUE(got.spherical);
  EXPECT_EQ(got.colourKind, want.colourKind);
  ASSERT_EQ(got.points.size(), want.points.size());
  for (size_t k = 0; k < got.cell.size(); ++k) {
    ASSERT_EQ(got.cell[k] < 0, want.cell[k] < 0) << "cell " << k;
    if (got.cell[k] < 0) continue;
    EXPECT_LE((got.points[got.cell[k]] - want.points[want.cell[k]]).norm(), tolerance)
        << "cell " << k;
    EXPECT_EQ(got.colours[got.cell[k]], want.colours[want.cell[k]]) << "cell " << k;
  }
}

}  // namespace

TEST(E57, Crc32cOfTheStandardCheckString) {
  const std::string check = "123456789";
  EXPECT_EQ(io::internal::crc32c(reinterpret_cast<const uint8_t*>(check.data()), 9), 0xE3069283u);
}

TEST(E57, Crc32cByInstructionIsTheTablesOnEveryLength) {
  std::mt19937 rng(7);
  std::string bytes(1100, '\0');
  for (char& c : bytes) c = static_cast<char>(rng());
  for (size_t n = 0; n <= bytes.size(); n += 1 + n / 7) {
    const auto* p = reinterpret_cast<const uint8_t*>(bytes.data()) + (n % 5);
    const size_t len = std::min(n, bytes.size() - n % 5);
    ASSERT_EQ(io::internal::crc32c(p, len), io::internal::crc32cPortable(p, len)) << n;
  }
}

TEST(E57, FieldBitsAreJustEnoughForTheRange) {
  io::E57Field f;
  for (const auto& [lo, hi, bits] : {std::tuple{0, 0, 0},
                                     {0, 1, 1},
                                     {0, 2, 2},
                                     {-1, 2, 2},
                                     {0, 255, 8},
                                     {0, 256, 9},
                                     {-1000, 1000, 11}}) {
    f.minimum = lo, f.maximum = hi;
    EXPECT_EQ(f.bits(), bits) << lo << ".." << hi;
  }
  f.minimum = INT64_MIN, f.maximum = INT64_MAX;
  EXPECT_EQ(f.bits(), 64);
  f.kind = io::E57Field::Kind::single;
  EXPECT_EQ(f.bits(), 32);
}

TEST(E57, StationsRoundTripInEveryCoordinateEncoding) {
  TempDir dir;
  const std::vector<RangeGrid> grids = {stationGrid(23, 17, 1, false), stationGrid(9, 31, 2, true)};
  std::vector<Pose> poses(2);
  poses[0].R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  poses[0].t = Eigen::Vector3d(1e5 + 0.125, -3, 7);
  poses[1].t = Eigen::Vector3d(0.5, 0.25, -1);
  using C = io::E57Coordinates;
  // Tolerances: doubles exact; singles to their rounding; scaled integers to half a step;
  // range, azimuth and elevation to the trigonometry's rounding.
  for (const auto& [coordinates, tolerance] : {std::pair{C::cartesianDouble, 0.0},
                                               {C::cartesianSingle, 1e-6},
                                               {C::cartesianScaled, 0.5e-4 * std::sqrt(3.0)},
                                               {C::sphericalDouble, 1e-12}})
    for (const int packetRecords : {0, 7, 100}) {
      io::E57Writing how;
      how.coordinates = coordinates, how.packetRecords = packetRecords;
      const std::string path = dir.file("stations.e57");
      io::writeE57(path, grids, poses, how);
      const std::vector<io::E57Scan> scans = io::indexE57(path);
      ASSERT_EQ(scans.size(), 2u);
      for (size_t i = 0; i < 2; ++i) {
        SCOPED_TRACE("encoding " + std::to_string(int(coordinates)) + ", packets of " +
                     std::to_string(packetRecords) + ", scan " + std::to_string(i));
        EXPECT_EQ(scans[i].name, "station " + std::to_string(i + 1));
        EXPECT_LE((scans[i].pose.R - poses[i].R).norm(), 1e-15);
        EXPECT_EQ(scans[i].pose.t, poses[i].t);
        EXPECT_EQ(scans[i].records, uint64_t(grids[i].cols) * grids[i].rows);
        expectSameGrid(io::readE57Scan(path, scans[i]), grids[i], tolerance);
      }
    }
}

TEST(E57, ScaledIntegersOfEveryWidthRoundTripToHalfAStep) {
  // Steps from 1 to 1e-18 of coordinates up to 5: integers of 4 to 64 bits, values spanning
  // bytes and (packets of 3 records) packets.
  TempDir dir;
  const RangeGrid grid = stationGrid(11, 7, 6, false);
  for (double step = 1; step > 5e-19; step /= 10) {
    io::E57Writing how;
    how.coordinates = io::E57Coordinates::cartesianScaled, how.scaledStep = step;
    how.packetRecords = 3;
    const std::string path = dir.file("scaled.e57");
    io::writeE57(path, {grid}, {Pose{}}, how);
    const io::E57Scan scan = io::indexE57(path).front();
    EXPECT_EQ(scan.fields[0].bits(), int(std::ceil(std::log2(2 * std::ceil(5 / step) + 3))))
        << "step " << step;
    SCOPED_TRACE("step " + std::to_string(step));
    // Past 53 bits the raw integers are rounded to doubles on both sides: a few ulps of 5.
    expectSameGrid(io::readE57Scan(path, scan), grid, 0.5 * step * std::sqrt(3.0) + 4e-15);
  }
}

TEST(E57, ColumnsOfAStationAreThoseOfTheWholeScan) {
  TempDir dir;
  const RangeGrid whole = stationGrid(20, 8, 3, false);
  const std::string path = dir.file("one.e57");
  io::writeE57(path, {whole}, {Pose{}});
  const io::E57Scan scan = io::indexE57(path).front();
  for (const auto& [first, count] : {std::pair{0, 20}, {0, 7}, {7, 6}, {13, 7}}) {
    const RangeGrid part = io::readE57Columns(path, scan, first, count);
    ASSERT_EQ(part.cols, count);
    for (int r = 0; r < whole.rows; ++r)
      for (int c = 0; c < count; ++c) {
        const int32_t a = part.at(r, c), b = whole.at(r, first + c);
        ASSERT_EQ(a < 0, b < 0);
        if (a >= 0) {
          EXPECT_EQ(part.points[a], whole.points[b]);
        }
      }
  }
}

TEST(E57, AStationWithColourAndIntensityIsReadAsEitherOnRequest) {
  // Colour by default; the intensity where --colour intensity asks (preferIntensity), the
  // writer's intensity being each colour's mean, to the single float's precision.
  TempDir dir;
  const RangeGrid g = stationGrid(16, 8, 4, true);
  const std::string path = dir.file("both.e57");
  io::E57Writing how;
  how.intensityToo = true;
  io::writeE57(path, {g}, {Pose{}}, how);
  io::ConfFile list = io::readScanList(path);
  EXPECT_EQ(io::readScanGrid(list.scans[0]).colourKind, ColourKind::rgb);
  io::preferIntensity(list);
  const RangeGrid grey = io::readScanGrid(list.scans[0]);
  ASSERT_EQ(grey.colourKind, ColourKind::intensity);
  ASSERT_EQ(grey.colours.size(), g.colours.size());
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c)
      if (g.at(r, c) >= 0) {
        EXPECT_NEAR(grey.colours[grey.at(r, c)].x(), g.colours[g.at(r, c)].mean(), 1e-6);
      }
}

TEST(E57, AScanWithoutIndicesIsProjectedOnAnAngularGrid) {
  // Points on a sphere at known azimuth and elevation steps of 2 degrees: the projection finds
  // a grid of about that step and keeps every point.
  RangeGrid g;
  g.rows = 30, g.cols = 90, g.spherical = true;
  g.colourKind = ColourKind::intensity;
  g.cell.assign(size_t(g.rows) * g.cols, -1);
  for (int c = 0; c < g.cols; ++c)
    for (int r = 0; r < g.rows; ++r) {
      const double az = (-90 + 2.0 * c) * M_PI / 180, el = (-30 + 2.0 * r) * M_PI / 180;
      g.cell[size_t(r) * g.cols + c] = static_cast<int32_t>(g.points.size());
      g.points.push_back(3 * Eigen::Vector3d(std::cos(el) * std::cos(az),
                                             std::cos(el) * std::sin(az), std::sin(el)));
      g.colours.push_back(Colour::Constant(0.25f));
    }
  TempDir dir;
  io::E57Writing how;
  how.structured = false;
  const std::string path = dir.file("loose.e57");
  io::writeE57(path, {g}, {Pose{}}, how);
  const io::E57Scan scan = io::indexE57(path).front();
  EXPECT_EQ(scan.rows, 0);
  std::string warning;
  const RangeGrid got = io::readE57Scan(path, scan, &warning);
  EXPECT_NE(warning.find("no row and column indices"), std::string::npos) << warning;
  EXPECT_EQ(got.points.size(), g.points.size());
  EXPECT_NEAR(got.cols, g.cols, 3);
  EXPECT_NEAR(got.rows, g.rows, 3);
}

TEST(E57, AChecksumErrorIsFoundOnEveryPage) {
  TempDir dir;
  const std::string path = dir.file("good.e57");
  io::writeE57(path, {stationGrid(30, 20, 4, true)}, {Pose{}});
  const std::string good = wholeFile(path);
  ASSERT_EQ(good.size() % 1024, 0u);
  ASSERT_GE(good.size() / 1024, 4u);
  EXPECT_EQ(message(path), "");
  for (size_t page = 0; page < good.size() / 1024; ++page) {
    std::string bad = good;
    bad[page * 1024 + 517] ^= 0x10;
    const std::string damaged = dir.write("damaged.e57", bad);
    EXPECT_NE(message(damaged).find("page " + std::to_string(page) + " (bytes " +
                                    std::to_string(page * 1024)),
              std::string::npos)
        << "page " << page << ": " << message(damaged);
  }
}

TEST(E57, TruncationAndDamageAreNamed) {
  TempDir dir;
  const std::string path = dir.file("good.e57");
  io::writeE57(path, {stationGrid(30, 20, 5, false)}, {Pose{}});
  const std::string good = wholeFile(path), text = logical(good);
  auto check = [&](const std::string& name, const std::string& bytes, const std::string& expect) {
    const std::string m = message(dir.write(name, bytes));
    EXPECT_NE(m.find(name), std::string::npos) << m;
    EXPECT_NE(m.find(expect), std::string::npos) << name << ": " << m;
  };
  check("cut.e57", good.substr(0, good.size() - 100), "not a whole number of 1024-byte");
  check("short.e57", good.substr(0, good.size() - 1024), "the header says");
  check("plain.e57", "hello", "not a whole number");
  std::string edited = text;
  edited.replace(0, 8, "ASTM-E58");
  check("signature.e57", paged(edited), "not an E57 file");
  // An edit of the XML that keeps its length (the header's), padded with spaces.
  auto xml = [&](const std::string& from, std::string to) {
    std::string t = text;
    const size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    EXPECT_LE(to.size(), from.size()) << to;
    to.resize(from.size(), ' ');
    t.replace(at, from.size(), to);
    return paged(t);
  };
  check("broken.e57", xml("<data3D type=", "<data3D type "), "XML: line");
  check("nocoords.e57", xml("<cartesianX ", "<cartesianQ "), "no coordinates");
  check("codec.e57",
        xml("<codecs type=\"Vector\" allowHeterogeneousChildren=\"1\"/>",
            "<codecs type=\"Vector\"><zip type=\"Structure\"/></codecs>"),
        "a codec other than the bit-pack codec");
  check("bounds.e57", xml("<rowMaximum type=\"Integer\">19<", "<rowMaximum type=\"Integer\">9 <"),
        "outside the stated index bounds");
  check("records.e57", xml("recordCount=\"600\"", "recordCount=\"900\""), "end after 600 of 900");
  check("type.e57", xml("<cartesianX type=\"Float\"", "<cartesianX type=\"Blob \""),
        "of type 'Blob '");
}

TEST(E57, FilesFromOtherWritersRead) {
  const std::string dir = std::string(RANGEFUSE_TEST_DATA) + "/e57/";
  // The reference implementation's bunny: scaled integers, an invalid-state field, no indices.
  const std::vector<io::E57Scan> bunny = io::indexE57(dir + "bunnyInt32.e57");
  ASSERT_EQ(bunny.size(), 1u);
  EXPECT_EQ(bunny[0].name, "bunny");
  EXPECT_EQ(bunny[0].records, 30571u);
  EXPECT_EQ(bunny[0].rows, 0);
  const RangeGrid b = io::readE57Scan(dir + "bunnyInt32.e57", bunny[0]);
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : b.points) box.extend(p);
  // The Stanford bunny's extent in metres (bun_zipper.ply: x -0.0947..0.0610, z -0.0619..0.0588).
  EXPECT_NEAR(box.min().x(), -0.0947, 1e-3);
  EXPECT_NEAR(box.max().x(), 0.0610, 1e-3);
  EXPECT_NEAR(box.min().z(), -0.0619, 1e-3);
  EXPECT_NEAR(box.max().z(), 0.0588, 1e-3);
  // libE57Format's cube: single floats on the faces of a unit cube, each face one colour.
  const std::vector<io::E57Scan> cube = io::indexE57(dir + "ColouredCubeFloat.e57");
  ASSERT_EQ(cube.size(), 1u);
  EXPECT_EQ(cube[0].records, 7680u);
  const RangeGrid c = io::readE57Scan(dir + "ColouredCubeFloat.e57", cube[0]);
  EXPECT_EQ(c.colourKind, ColourKind::rgb);
  for (size_t k = 0; k < c.points.size(); ++k) {
    ASSERT_NEAR(c.points[k].cwiseAbs().maxCoeff(), 0.5, 1e-6) << "point " << k;
    for (int a = 0; a < 3; ++a) {
      ASSERT_TRUE(c.colours[k][a] == 0 || c.colours[k][a] == 1) << "point " << k;
    }
  }
  EXPECT_NE(message(dir + "bad-crc.e57").find("page 0 (bytes 0-1023): checksum mismatch"),
            std::string::npos)
      << message(dir + "bad-crc.e57");
}
