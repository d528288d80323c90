// Depth-image sequences: 16-bit PNG round trips, the depth image's grid against hand-computed
// camera points, nearest-timestamp matching, TUM and Redwood folders written and read back, and
// each malformed input refused with the file (and line) at fault.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "SequenceParts.h"
#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/DepthSequence.h"
#include "rangefuse/io/Jpeg.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/ScanFiles.h"

using namespace rangefuse;
using test::TempDir;

namespace {

io::DepthImage randomImage(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  io::DepthImage image{width, height, std::vector<uint16_t>(size_t(width) * height)};
  for (uint16_t& c : image.counts) c = rng() % 4 == 0 ? 0 : static_cast<uint16_t>(rng());
  image.counts[0] = 65535;
  return image;
}

io::DepthCamera camera(int width, int height) {
  io::DepthCamera c;
  c.fx = 525, c.fy = 520, c.cx = 0.5 * (width - 1) + 0.25, c.cy = 0.5 * (height - 1) - 0.5;
  c.width = width, c.height = height;
  return c;
}

Pose randomPose(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Pose p;
  p.R = Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized())
            .toRotationMatrix();
  p.t = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

std::vector<io::DepthFrame> frames(int n) {
  std::vector<io::DepthFrame> out;
  for (int k = 0; k < n; ++k) out.push_back({randomImage(9, 7, 10 + k), randomPose(20 + k)});
  return out;
}

/// The message of reading the folder or list, or "" when it reads.
std::string failure(const std::string& path, const io::ScanSourceOptions& source = {}) {
  try {
    for (const io::ConfScan& s : io::readScanList(path, {}, source).scans) io::readScanGrid(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expectMessage(const std::string& message, const std::string& part) {
  EXPECT_NE(message.find(part), std::string::npos) << "'" << message << "' lacks '" << part << "'";
}

}  // namespace

TEST(DepthPng, SixteenBitCountsRoundTripExactly) {
  TempDir dir;
  const io::DepthImage image = randomImage(13, 5, 1);
  io::writeDepthPng(dir.file("d.png"), image);
  const io::DepthImage back = io::readDepthPng(dir.file("d.png"), 1000);
  EXPECT_EQ(back.width, 13);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.counts, image.counts);
  EXPECT_FALSE(std::filesystem::exists(dir.file("d.png.tmp")));
}

TEST(DepthPng, AByteChangedInThePixelsIsRefused) {
  // The reader skips zlib's checksum of the pixels: the chunk's CRC must still catch a change.
  TempDir dir;
  io::writeDepthPng(dir.file("d.png"), randomImage(40, 30, 2));
  std::string bytes;
  {
    std::ifstream in(dir.file("d.png"), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t data = bytes.find("IDAT");
  ASSERT_NE(data, std::string::npos);
  bytes[data + 4 + 40] ^= 0x10;  // well inside the compressed pixels
  const std::string path = dir.write("changed.png", bytes);
  std::string message;
  try {
    io::readDepthPng(path, 10000);
  } catch (const InputError& e) {
    message = e.what();
  }
  expectMessage(message, "changed.png: corrupt or truncated PNG");
}

TEST(DepthPng, PixelsComeFromTheHeaderAloneAndZeroForWhatIsNoPng) {
  TempDir dir;
  io::writeDepthPng(dir.file("d.png"), randomImage(37, 23, 4));
  EXPECT_EQ(io::pngPixels(dir.file("d.png")), 37u * 23u);
  io::writePng(dir.file("rgb.png"), Image(4, 3, 0));
  EXPECT_EQ(io::pngPixels(dir.file("rgb.png")), 12u);  // any PNG: its reader judges the format
  EXPECT_EQ(io::pngPixels(dir.write("text.png", "not an image at all, but long enough")), 0u);
  EXPECT_EQ(io::pngPixels(dir.write("short.png", "\x89PNG")), 0u);
  EXPECT_EQ(io::pngPixels(dir.file("none.png")), 0u);
}

TEST(DepthPng, RefusesColourTruncatedMissingAndOversizedFiles) {
  TempDir dir;
  io::writePng(dir.file("rgb.png"), Image(4, 3, 0));
  expectMessage(
      [&] {
        try {
          io::readDepthPng(dir.file("rgb.png"), 1000);
        } catch (const InputError& e) {
          return std::string(e.what());
        }
        return std::string();
      }(),
      "rgb.png: not a 16-bit greyscale PNG");
  io::writeDepthPng(dir.file("d.png"), randomImage(40, 30, 2));
  std::filesystem::resize_file(dir.file("d.png"),
                               std::filesystem::file_size(dir.file("d.png")) / 2);
  EXPECT_THROW(io::readDepthPng(dir.file("d.png"), 10000), InputError);
  EXPECT_THROW(io::readDepthPng(dir.file("none.png"), 10000), InputError);
  io::writeDepthPng(dir.file("big.png"), randomImage(40, 30, 3));
  EXPECT_THROW(io::readDepthPng(dir.file("big.png"), 1199), InputError);
  EXPECT_NO_THROW(io::readDepthPng(dir.file("big.png"), 1200));
}

TEST(DepthCamera, GridPointsAreTheCameraPointsInTheScanFrame) {
  const io::DepthCamera cam = camera(9, 7);
  const io::DepthImage image = randomImage(9, 7, 4);
  const RangeGrid g = io::depthGrid(image, cam, "test");
  const Pose cameraToWorld = randomPose(5), scanToWorld = io::scanPose(cameraToWorld);
  ASSERT_TRUE(g.pinhole);
  int seen = 0;
  for (int v = 0; v < 7; ++v)
    for (int u = 0; u < 9; ++u) {
      const int32_t k = g.at(6 - v, u);
      const double d = image.at(u, v) * cam.unit;
      ASSERT_EQ(k < 0, image.at(u, v) == 0) << u << ", " << v;
      if (k < 0) continue;
      ++seen;
      const Eigen::Vector3d camPoint((u - cam.cx) * d / cam.fx, (v - cam.cy) * d / cam.fy, d);
      EXPECT_LT((scanToWorld.apply(g.points[k]) - cameraToWorld.apply(camPoint)).norm(), 1e-12);
      // The grid's own pinhole (rows from the bottom) sends the point back to its cell.
      const Eigen::Vector3d& p = g.points[k];
      EXPECT_NEAR(g.pinhole->cx + g.pinhole->fx * p.x() / -p.z(), u, 1e-9);
      EXPECT_NEAR(g.pinhole->cy + g.pinhole->fy * p.y() / -p.z(), 6 - v, 1e-9);
    }
  EXPECT_GT(seen, 30);
  EXPECT_LT((io::cameraPose(scanToWorld).R - cameraToWorld.R).norm(), 1e-15);
  EXPECT_GT(scanToWorld.R.determinant(), 0.999);
}

TEST(DepthCamera, FarMeasurementsAreDroppedAndSizeMismatchesRefused) {
  io::DepthCamera cam = camera(9, 7);
  cam.depthMax = 30.0;  // counts above 30000 at 1 mm
  const io::DepthImage image = randomImage(9, 7, 6);
  const RangeGrid g = io::depthGrid(image, cam, "test");
  size_t kept = 0;
  for (uint16_t c : image.counts) kept += c > 0 && c <= 30000;
  EXPECT_EQ(g.points.size(), kept);
  EXPECT_THROW(io::depthGrid(image, camera(8, 7), "f.png"), InputError);
}

TEST(DepthSequence, NearestTimestampWithinTheLimit) {
  const std::vector<double> poses = {1.00, 1.01, 1.02, 1.10};
  const std::vector<long> match =
      io::nearestTimes({0.97, 0.995, 1.014, 1.016, 1.06, 1.13, 1.2}, poses, 0.02);
  EXPECT_EQ(match, (std::vector<long>{-1, 0, 1, 2, -1, -1, -1}));
  EXPECT_EQ(io::nearestTimes({1.09}, poses, 0.02), (std::vector<long>{3}));
}

TEST(DepthSequence, TumFolderRoundTripsFramesAndPoses) {
  TempDir dir;
  const auto written = frames(4);
  io::writeTumSequence(dir.file("tum"), written, camera(9, 7));
  EXPECT_EQ(io::sequenceLayout(dir.file("tum")), io::SequenceLayout::Tum);
  const io::ConfFile list = io::readScanList(dir.file("tum"));
  ASSERT_EQ(list.scans.size(), 4u);
  EXPECT_TRUE(list.warnings.empty());
  for (size_t k = 0; k < 4; ++k) {
    const io::ConfScan& s = list.scans[k];
    EXPECT_EQ(s.name.rfind("depth/", 0), 0u);
    ASSERT_TRUE(s.depth);
    EXPECT_DOUBLE_EQ(s.depth->unit, 1.0 / 5000);
    const Pose cam = io::cameraPose(s.pose);
    EXPECT_LT((cam.R - written[k].cameraToWorld.R).norm(), 1e-14);
    EXPECT_LT((cam.t - written[k].cameraToWorld.t).norm(), 1e-15);
    const RangeGrid g = io::readScanGrid(s);
    EXPECT_EQ(g.points, io::depthGrid(written[k].image, *s.depth, "").points);
  }
}

TEST(DepthSequence, RedwoodFolderRoundTripsAndAConfMayNameItsImages) {
  TempDir dir;
  const auto written = frames(3);
  io::writeRedwoodSequence(dir.file("rw"), written, camera(9, 7));
  EXPECT_EQ(io::sequenceLayout(dir.file("rw")), io::SequenceLayout::Redwood);
  const io::ConfFile list = io::readScanList(dir.file("rw"));
  ASSERT_EQ(list.scans.size(), 3u);
  EXPECT_EQ(list.scans[2].name, "depth/000002.png");
  EXPECT_DOUBLE_EQ(list.scans[2].depth->unit, 1e-3);
  for (size_t k = 0; k < 3; ++k)
    EXPECT_LT((io::cameraPose(list.scans[k].pose).t - written[k].cameraToWorld.t).norm(), 1e-15);
  // Refined poses written beside the sequence read back with the same camera.
  io::writeConf(dir.file("rw/poses.conf"), list.scans);
  const io::ConfFile named = io::readScanList(dir.file("rw/poses.conf"));
  ASSERT_EQ(named.scans.size(), 3u);
  ASSERT_TRUE(named.scans[1].depth);
  EXPECT_EQ(named.scans[1].depth->fx, 525);
  EXPECT_EQ(io::readScanGrid(named.scans[1]).points, io::readScanGrid(list.scans[1]).points);
  // --intrinsics overrides the folder's camera.
  io::ScanSourceOptions given;
  given.intrinsics = "500,500,4,3";
  EXPECT_EQ(io::readScanList(dir.file("rw"), {}, given).scans[0].depth->fx, 500);
}

TEST(DepthSequence, FramesWithoutAPoseNearbyAreLeftOutWithAWarning) {
  TempDir dir;
  io::writeTumSequence(dir.file("tum"), frames(3), camera(9, 7));
  // Keep only the first frame's pose: the others are 33 and 67 ms away.
  std::ifstream in(dir.file("tum/groundtruth.txt"));
  std::string line, kept;
  for (int n = 0; std::getline(in, line) && n < 3; ++n) kept += line + "\n";
  dir.write("tum/groundtruth.txt", kept);
  const io::ConfFile list = io::readScanList(dir.file("tum"));
  EXPECT_EQ(list.scans.size(), 1u);
  ASSERT_EQ(list.warnings.size(), 1u);
  expectMessage(list.warnings[0], "2 of 3 depth frames have no pose");
}

TEST(DepthSequence, MalformedTumFoldersNameTheFileAndLine) {
  TempDir dir;
  auto fresh = [&] {
    std::filesystem::remove_all(dir.file("tum"));
    io::writeTumSequence(dir.file("tum"), frames(3), camera(9, 7));
  };
  fresh();
  dir.write("tum/depth.txt", "1.0 depth/1000.000000.png\n0.5 depth/1000.033333.png\n");
  expectMessage(failure(dir.file("tum")), "depth.txt: line 2: timestamps out of order");
  fresh();
  dir.write("tum/depth.txt", "1000.0 depth/1000.000000.png\n1000.1 depth/gone.png\n");
  expectMessage(failure(dir.file("tum")), "depth.txt: line 2: depth/gone.png does not exist");
  fresh();
  dir.write("tum/groundtruth.txt", "# poses\n1000.0 0 0 0 0 0 0\n");
  expectMessage(failure(dir.file("tum")), "groundtruth.txt: line 2: expected");
  fresh();
  dir.write("tum/groundtruth.txt", "1000.0 0 0 nan 0 0 0 1\n");
  expectMessage(failure(dir.file("tum")), "groundtruth.txt: line 1: NaN or Inf");
  fresh();
  dir.write("tum/groundtruth.txt", "1000.0 0 0 0 0 0 0 2\n");
  expectMessage(failure(dir.file("tum")), "line 1: quaternion is not of unit length");
  fresh();
  std::filesystem::remove(dir.file("tum/camera_intrinsic.json"));
  expectMessage(failure(dir.file("tum")), "no camera intrinsics");
  EXPECT_EQ(failure(dir.file("tum"), {"auto", "525,525,4,3", 0}), "");
  expectMessage(failure(dir.file("tum"), {"auto", "525,525,4", 0}), "--intrinsics");
  fresh();
  dir.write("tum/camera_intrinsic.json", "{\"width\": 9}");
  expectMessage(failure(dir.file("tum")), "camera_intrinsic.json: not a camera intrinsic file");
  fresh();
  io::writeDepthPng(dir.file("tum/depth/1000.033333.png"), randomImage(8, 7, 1));
  expectMessage(failure(dir.file("tum")), "1000.033333.png: image is 8 x 7 pixels");
  fresh();
  dir.write("tum/depth/1000.066667.png", "not a png");
  expectMessage(failure(dir.file("tum")), "1000.066667.png: corrupt or truncated PNG");
}

TEST(DepthSequence, MalformedRedwoodFoldersNameTheFileAndLine) {
  TempDir dir;
  auto fresh = [&] {
    std::filesystem::remove_all(dir.file("rw"));
    io::writeRedwoodSequence(dir.file("rw"), frames(2), camera(9, 7));
  };
  fresh();
  std::filesystem::remove(dir.file("rw/depth/000001.png"));
  expectMessage(failure(dir.file("rw")), "trajectory.log: 2 poses but");
  fresh();
  dir.write("rw/trajectory.log", "0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n");
  expectMessage(failure(dir.file("rw")), "trajectory.log: 4 lines");
  fresh();
  dir.write(
      "rw/trajectory.log",
      "0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n1 1 2\n2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  expectMessage(failure(dir.file("rw")), "trajectory.log: line 7: the matrix is not rigid");
  fresh();
  dir.write("rw/trajectory.log",
            "0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n1 1 2\n1 0 0 0\n0 1 0\n0 0 1 0\n0 0 0 1\n");
  expectMessage(failure(dir.file("rw")), "trajectory.log: line 8: expected a matrix row");
  std::filesystem::create_directories(dir.file("empty"));
  expectMessage(failure(dir.file("empty")), "empty: a folder of scans must be");
  expectMessage(failure(dir.file("rw"), {"ptx", "", 0}), "rw");
  expectMessage(failure(dir.file("rw"), {"las", "", 0}), "--scan-format 'las': must be auto,");
  expectMessage(failure(dir.file("rw"), {"e57", "", 0}), "rw: is a folder, not an E57 file");
}

TEST(DepthSequence, FoldersWithoutATrajectoryAreReadUnposedInOrder) {
  TempDir dir;
  const auto written = frames(3);
  io::writeTumSequence(dir.file("tum"), written, camera(9, 7));
  std::filesystem::remove(dir.file("tum/groundtruth.txt"));
  const io::ConfFile tum = io::readScanList(dir.file("tum"));
  EXPECT_FALSE(tum.posed);
  ASSERT_EQ(tum.scans.size(), 3u);
  EXPECT_NEAR(tum.scans[1].time, 1000 + 1 / 30.0, 1e-6);  // as named, to the microsecond
  // Open3D's recorder: depth/NNNNNN.png and camera_intrinsic.json, colour beside, no .log.
  io::writeRedwoodSequence(dir.file("rec"), written, camera(9, 7));
  std::filesystem::remove(dir.file("rec/trajectory.log"));
  std::filesystem::create_directories(dir.file("rec/color"));
  const io::ConfFile rec = io::readScanList(dir.file("rec"));
  EXPECT_FALSE(rec.posed);
  ASSERT_EQ(rec.scans.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(rec.scans[k].name, "depth/00000" + std::to_string(k) + ".png");
    EXPECT_DOUBLE_EQ(rec.scans[k].time, k / 30.0);
    // Every frame at the first camera's pose, the identity.
    EXPECT_LT((io::cameraPose(rec.scans[k].pose).R - Eigen::Matrix3d::Identity()).norm(), 1e-15);
    EXPECT_EQ(io::readScanGrid(rec.scans[k]).points,
              io::depthGrid(written[k].image, *rec.scans[k].depth, "").points);
  }
}

TEST(DepthSequence, DepthScaleAndFoldersOfColourAloneAreCheckedByName) {
  TempDir dir;
  io::DepthImage near{9, 7, std::vector<uint16_t>(63, 1500)};  // 1.5 m at 1 mm a count
  io::writeRedwoodSequence(dir.file("rec"), {{near, Pose{}}}, camera(9, 7));
  io::ScanSourceOptions source;
  source.depthScale = 2000;  // counts a metre: half the depth
  const io::ConfScan frame = io::readScanList(dir.file("rec"), {}, source).scans[0];
  EXPECT_NEAR(-io::readScanGrid(frame).points[0].z(), 0.75, 1e-12);
  source.depthScale = 1;  // counts read as metres: 1.5 km
  expectMessage(failure(dir.file("rec"), source),
                "000000.png: every depth lies beyond 100 m at 1 counts a metre");
  std::filesystem::create_directories(dir.file("colour/color"));
  expectMessage(failure(dir.file("colour")), "colour: holds colour images (color/) but no depth");
}

namespace {

/// Frames with colour images whose pixel (u, v) holds (u, v, frame) in its channels.
std::vector<io::DepthFrame> colouredFrames(int n) {
  std::vector<io::DepthFrame> out = frames(n);
  for (int k = 0; k < n; ++k) {
    Image c(9, 7, 0);
    for (int v = 0; v < 7; ++v)
      for (int u = 0; u < 9; ++u)
        c.set(u, v, static_cast<uint8_t>(10 * u), static_cast<uint8_t>(20 * v),
              static_cast<uint8_t>(k));
    out[k].colour = c;
  }
  return out;
}

/// Each point's colour against its pixel's in the image written.
void expectPixelColours(const RangeGrid& g, const Image& written) {
  ASSERT_EQ(g.colourKind, ColourKind::rgb);
  ASSERT_EQ(g.colours.size(), g.points.size());
  for (int r = 0; r < g.rows; ++r)
    for (int u = 0; u < g.cols; ++u) {
      const int32_t k = g.at(r, u);
      if (k < 0) continue;
      const uint8_t* p = &written.rgb[(size_t(g.rows - 1 - r) * g.cols + u) * 3];
      for (int ch = 0; ch < 3; ++ch) EXPECT_FLOAT_EQ(g.colours[k][ch], p[ch] / 255.0f);
    }
}

}  // namespace

TEST(DepthSequence, ColourImagesReachTheirFramesPoints) {
  TempDir dir;
  const auto written = colouredFrames(3);
  io::writeTumSequence(dir.file("tum"), written, camera(9, 7));
  io::writeRedwoodSequence(dir.file("rw"), written, camera(9, 7));
  for (const char* folder : {"tum", "rw"}) {
    const io::ConfFile list = io::readScanList(dir.file(folder));
    ASSERT_EQ(list.scans.size(), 3u) << folder;
    for (size_t k = 0; k < 3; ++k)
      expectPixelColours(io::readScanGrid(list.scans[k]), written[k].colour);
  }
}

TEST(DepthSequence, ColourImagesOfTheWrongSizeOrCountAreRefusedByName) {
  TempDir dir;
  auto written = colouredFrames(3);
  written[1].colour = Image(8, 7, 0);
  io::writeTumSequence(dir.file("tum"), written, camera(9, 7));
  EXPECT_NE(failure(dir.file("tum"))
                .find("rgb/1000.033333.png: colour image is 8 x 7 pixels but "
                      "its depth image is 9 x 7"),
            std::string::npos)
      << failure(dir.file("tum"));
  io::writeRedwoodSequence(dir.file("rw"), colouredFrames(3), camera(9, 7));
  std::filesystem::remove(dir.file("rw/color/000002.png"));
  EXPECT_NE(failure(dir.file("rw")).find("color holds 2 colour images but depth/ 3"),
            std::string::npos)
      << failure(dir.file("rw"));
  // A folder without PNG or JPEG images: a warning, and the frames are read without colour.
  std::filesystem::remove_all(dir.file("rw/color"));
  std::filesystem::create_directories(dir.file("rw/color"));
  std::ofstream(dir.file("rw/color/000000.bmp")) << "not an image we read";
  const io::ConfFile list = io::readScanList(dir.file("rw"));
  ASSERT_EQ(list.warnings.size(), 1u);
  EXPECT_NE(list.warnings[0].find("no PNG or JPEG images"), std::string::npos) << list.warnings[0];
  EXPECT_TRUE(io::readScanGrid(list.scans[0]).colours.empty());
}

TEST(DepthSequence, JpegColourImagesAsTheRecorderWritesThem) {
  // Open3D's recorder writes color/*.jpg beside depth/*.png. JPEG is lossy: at quality 100 and
  // full-resolution chroma, ramps stay within a few levels.
  TempDir dir;
  const auto written = colouredFrames(3);
  io::writeRedwoodSequence(dir.file("rec"), written, camera(9, 7));
  for (int k = 0; k < 3; ++k) {
    const std::string png = dir.file("rec/color/00000" + std::to_string(k) + ".png");
    io::writeJpeg(dir.file("rec/color/00000" + std::to_string(k) + ".jpg"), io::readPng(png), 100);
    std::filesystem::remove(png);
  }
  const io::ConfFile list = io::readScanList(dir.file("rec"));
  ASSERT_TRUE(list.warnings.empty());
  for (size_t k = 0; k < 3; ++k) {
    const RangeGrid g = io::readScanGrid(list.scans[k]);
    ASSERT_EQ(g.colours.size(), g.points.size());
    const Image& want = written[k].colour;
    for (int r = 0; r < g.rows; ++r)
      for (int u = 0; u < g.cols; ++u) {
        const int32_t at = g.at(r, u);
        if (at < 0) continue;
        const uint8_t* p = &want.rgb[(size_t(g.rows - 1 - r) * g.cols + u) * 3];
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(g.colours[at][ch] * 255, p[ch], 3) << k;
      }
  }
  // A damaged JPEG is refused by name with libjpeg's reason.
  std::ofstream(dir.file("rec/color/000001.jpg"), std::ios::trunc) << "GIF89a";
  std::string message;
  try {
    io::readScanGrid(list.scans[1]);
  } catch (const InputError& e) {
    message = e.what();
  }
  expectMessage(message, "000001.jpg: cannot read JPEG: Not a JPEG file");
}

TEST(Jpeg, GreyscaleBecomesRgbAndLimitsHold) {
  TempDir dir;
  Image grey(16, 8, 0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) grey.set(x, y, 100, 100, 100);
  io::writeJpeg(dir.file("g.jpg"), grey, 100);
  const Image back = io::readColourImage(dir.file("g.jpg"), 1000);
  ASSERT_EQ(back.width, 16);
  ASSERT_EQ(back.height, 8);
  for (uint8_t v : back.rgb) EXPECT_NEAR(v, 100, 1);
  std::string message;
  try {
    io::readJpeg(dir.file("g.jpg"), 100);
  } catch (const InputError& e) {
    message = e.what();
  }
  expectMessage(message, "g.jpg: cannot read JPEG: holds 16 x 8 pixels, more than");
  try {
    io::readColourImage(dir.file("g.tif"), 1000);
  } catch (const InputError& e) {
    message = e.what();
  }
  expectMessage(message, "g.tif: colour images must be PNG or JPEG");
}

TEST(DepthSequence, SevenScenesFolderRoundTripsWithAndWithoutPoses) {
  TempDir dir;
  const auto written = frames(3);
  io::writeSevenScenesSequence(dir.file("7s"), written, camera(9, 7));
  EXPECT_EQ(io::sequenceLayout(dir.file("7s")), io::SequenceLayout::SevenScenes);
  const io::ConfFile list = io::readScanList(dir.file("7s"));
  EXPECT_TRUE(list.posed);
  ASSERT_EQ(list.scans.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    const io::ConfScan& s = list.scans[k];
    EXPECT_EQ(s.name, "frame-00000" + std::to_string(k) + ".depth.png");
    EXPECT_DOUBLE_EQ(s.time, k / 30.0);
    ASSERT_TRUE(s.depth);
    EXPECT_DOUBLE_EQ(s.depth->unit, 1e-3);
    EXPECT_EQ(s.depth->fx, 525);
    EXPECT_EQ(s.depth->cy, 0.5 * (7 - 1) - 0.5);
    const Pose cam = io::cameraPose(s.pose);
    EXPECT_LT((cam.R - written[k].cameraToWorld.R).norm(), 1e-14);
    EXPECT_LT((cam.t - written[k].cameraToWorld.t).norm(), 1e-15);
    EXPECT_EQ(io::readScanGrid(s).points, io::depthGrid(written[k].image, *s.depth, "").points);
  }
  // A .conf beside the frames names them and finds their camera.
  io::writeConf(dir.file("7s/refined.conf"), list.scans);
  const io::ConfFile named = io::readScanList(dir.file("7s/refined.conf"));
  ASSERT_EQ(named.scans.size(), 3u);
  ASSERT_TRUE(named.scans[2].depth);
  EXPECT_EQ(named.scans[2].depth->fx, 525);
  // Without pose files: every frame unposed, in number order (a gap keeps its time).
  io::writeSevenScenesSequence(dir.file("bare"), written, camera(9, 7), false);
  std::filesystem::rename(dir.file("bare/frame-000002.depth.png"),
                          dir.file("bare/frame-000010.depth.png"));
  const io::ConfFile bare = io::readScanList(dir.file("bare"));
  EXPECT_FALSE(bare.posed);
  ASSERT_EQ(bare.scans.size(), 3u);
  EXPECT_EQ(bare.scans[2].name, "frame-000010.depth.png");
  EXPECT_DOUBLE_EQ(bare.scans[2].time, 10 / 30.0);
  EXPECT_LT((io::cameraPose(bare.scans[1].pose).t).norm(), 1e-15);
  // The camera matrix file is also an --intrinsics file.
  std::filesystem::remove(dir.file("bare/camera-intrinsics.txt"));
  io::ScanSourceOptions given;
  given.intrinsics = dir.file("7s/camera-intrinsics.txt");
  EXPECT_EQ(io::readScanList(dir.file("bare"), {}, given).scans[0].depth->fx, 525);
}

TEST(DepthSequence, SevenScenesNamesGiveTheirFrameNumber) {
  using io::internal::sevenScenesNumber;
  EXPECT_EQ(sevenScenesNumber("frame-000012.depth.png", "depth.png"), 12);
  EXPECT_EQ(sevenScenesNumber("frame-1.depth.png", "depth.png"), 1);
  EXPECT_EQ(sevenScenesNumber("frame-123456789.pose.txt", "pose.txt"), 123456789);
  EXPECT_EQ(sevenScenesNumber("frame-000012.pose.txt", "depth.png"), -1);  // the other kind
  EXPECT_EQ(sevenScenesNumber("frame-000012.color.png", "color.png"), -1);
  for (const char* name : {"frame-.depth.png", "frame-1234567890.depth.png", "frame-12a.depth.png",
                           "xframe-1.depth.png", "frame-1.depth.png.bak", "frame-1xdepth.png",
                           "frame--1.depth.png", "depth.png", ""})
    EXPECT_EQ(sevenScenesNumber(name, "depth.png"), -1) << name;
}

TEST(DepthSequence, MalformedSevenScenesFoldersNameTheFile) {
  TempDir dir;
  auto fresh = [&] {
    std::filesystem::remove_all(dir.file("7s"));
    io::writeSevenScenesSequence(dir.file("7s"), frames(3), camera(9, 7));
  };
  fresh();
  dir.write("7s/frame-000001.pose.txt", "2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  expectMessage(failure(dir.file("7s")), "frame-000001.pose.txt: the matrix is not rigid");
  fresh();
  dir.write("7s/frame-000001.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n");
  expectMessage(failure(dir.file("7s")), "frame-000001.pose.txt: the last row is not '0 0 0 1'");
  fresh();
  dir.write("7s/frame-000002.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n");
  expectMessage(failure(dir.file("7s")), "frame-000002.pose.txt: expected a 4 x 4");
  fresh();
  std::filesystem::remove(dir.file("7s/frame-000001.pose.txt"));
  expectMessage(failure(dir.file("7s")),
                "frame-000001.pose.txt: missing (3 depth images but 2 pose files)");
  fresh();
  std::filesystem::remove(dir.file("7s/frame-000002.depth.png"));
  expectMessage(failure(dir.file("7s")),
                "frame-000002.pose.txt: a pose without its depth image frame-000002.depth.png");
  fresh();
  std::filesystem::remove(dir.file("7s/camera-intrinsics.txt"));
  expectMessage(failure(dir.file("7s")), "7s: no camera intrinsics");
  EXPECT_EQ(failure(dir.file("7s"), {"auto", "525,525,4,3", 0}), "");
  fresh();
  dir.write("7s/camera-intrinsics.txt", "585 0 320\n0 585 240\n");
  expectMessage(failure(dir.file("7s")), "camera-intrinsics.txt: expected a 3 x 3 camera matrix");
  dir.write("7s/camera-intrinsics.txt", "585 1 320\n0 585 240\n0 0 1\n");
  expectMessage(failure(dir.file("7s")), "camera-intrinsics.txt: not a pinhole camera matrix");
  dir.write("7s/camera-intrinsics.txt", "585 0 320\n0 585\n0 0 1\n");
  expectMessage(failure(dir.file("7s")),
                "camera-intrinsics.txt: line 2: expected a matrix row of 3 numbers");
  fresh();
  // Forced onto another layout, and another layout forced onto it.
  io::writeRedwoodSequence(dir.file("rw"), frames(2), camera(9, 7));
  expectMessage(failure(dir.file("rw"), {"7scenes", "", 0}), "it holds depth");
  EXPECT_EQ(failure(dir.file("7s"), {"7scenes", "", 0}), "");
  expectMessage(failure(dir.file("7s"), {"redwood", "", 0}), "as a 7-Scenes folder's");
  expectMessage(failure(dir.file("7s"), {"tum", "", 0}), "as a 7-Scenes folder's");
}
