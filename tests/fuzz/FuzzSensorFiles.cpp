// Fuzz entries for the sensor formats that arrive as files on disk (Leica PTX, 16-bit PNG,
// depth-image folders): the readers take paths, so the bytes are written into a scratch folder
// this process owns and read back exactly as the tool reads them.
#include <stdlib.h>

#include <filesystem>
#include <fstream>

#include "../../io/E57Pages.h"
#include "FuzzEntries.h"
#include "rangefuse/io/DepthPng.h"
#include "rangefuse/io/E57.h"
#include "rangefuse/io/Jpeg.h"
#include "rangefuse/io/Ptx.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/route/ScanLoader.h"

namespace fs = std::filesystem;

namespace rangefuse::fuzz {
namespace {

/// A folder of our own under the temporary directory, made on first use. Left behind at exit
/// (a few small files): libFuzzer ends processes in ways no destructor sees.
const fs::path& scratch() {
  static const fs::path dir = [] {
    std::string name = (fs::temp_directory_path() / "rangefuse_fuzz_XXXXXX").string();
    if (!mkdtemp(name.data())) std::abort();
    return fs::path(name);
  }();
  return dir;
}

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// `bytes` cut at NUL bytes: one part per file of a folder.
std::vector<std::string> parts(const std::string& bytes) {
  std::vector<std::string> out(1);
  for (char c : bytes)
    if (c == '\0')
      out.emplace_back();
    else
      out.back() += c;
  return out;
}

/// A sequence folder: two valid 4 x 3 frames named as TUM timestamps (Redwood takes any
/// names), then the layout's text files from the parts (a missing part: a missing file).
fs::path sequenceFolder(bool tum, const std::vector<std::string>& text) {
  const fs::path dir = scratch() / "sequence";
  fs::remove_all(dir);
  fs::create_directories(dir / "depth");
  const io::DepthImage frame{
      4, 3, {0, 5000, 5100, 5200, 5000, 5000, 5000, 0, 4900, 5000, 5050, 5000}};
  io::writeDepthPng((dir / "depth" / "1000.000000.png").string(), frame);
  io::writeDepthPng((dir / "depth" / "1000.033333.png").string(), frame);
  const std::vector<const char*> names =
      tum ? std::vector<const char*>{"depth.txt", "groundtruth.txt", "camera_intrinsic.json"}
          : std::vector<const char*>{"trajectory.log", "camera_intrinsic.json"};
  for (size_t k = 0; k < names.size() && k < text.size(); ++k) writeBytes(dir / names[k], text[k]);
  return dir;
}

}  // namespace

void ptx(const std::string& bytes) {
  const fs::path file = scratch() / "fuzz.ptx";
  writeBytes(file, bytes);
  refusedCleanly([&] {
    for (const io::PtxScan& scan : io::indexPtx(file.string(), fuzzLimits())) {
      io::readPtxScan(file.string(), scan);
      // Read and prepared again in two bands of columns, as fuse reads a large station.
      io::ConfScan band{"fuzz.ptx#1", file.string(), scan.pose, scan};
      band.bands = 2;
      SurfaceOptions merged;
      merged.mergeTarget = 0.5;
      merged.sightMap = true;
      for (band.band = 0; band.band < 2; ++band.band) loadScan(band, merged, fuzzLimits(), 0.1);
    }
  });
}

void e57(const std::string& bytes) {
  const fs::path file = scratch() / "fuzz.e57";
  std::string content = bytes.empty() ? bytes : bytes.substr(1);
  if (!bytes.empty() && (bytes[0] & 1) == 0) {
    // The header's file length follows the pages, so that a mutation's length is no obstacle.
    const uint64_t pages = (content.size() + io::internal::kE57PageData - 1) /
                           io::internal::kE57PageData * io::internal::kE57Page;
    for (int k = 0; k < 8 && content.size() >= 24; ++k)
      content[16 + k] = static_cast<char>(pages >> (8 * k) & 0xFF);
    std::string paged;
    for (size_t at = 0; at < content.size(); at += io::internal::kE57PageData) {
      std::string page = content.substr(at, io::internal::kE57PageData);
      page.resize(io::internal::kE57PageData, '\0');
      const uint32_t crc =
          io::internal::crc32c(reinterpret_cast<const uint8_t*>(page.data()), page.size());
      for (int k = 3; k >= 0; --k) page.push_back(static_cast<char>(crc >> (8 * k) & 0xFF));
      paged += page;
    }
    content = paged;
  }
  writeBytes(file, content);
  refusedCleanly([&] {
    const std::vector<io::E57Scan> scans = io::indexE57(file.string(), fuzzLimits());
    for (const io::E57Scan& scan : scans) {
      io::readE57Scan(file.string(), scan);
      if (scan.rows == 0) continue;
      // Read and prepared again in two bands of columns, as fuse reads a large station.
      io::ConfScan band{"fuzz.e57#1", file.string(), scan.pose};
      band.e57 = scan;
      band.bands = 2;
      SurfaceOptions merged;
      merged.mergeTarget = 0.5;
      merged.sightMap = true;
      for (band.band = 0; band.band < 2; ++band.band) loadScan(band, merged, fuzzLimits(), 0.1);
    }
  });
}

void depthPng(const std::string& bytes) {
  const fs::path file = scratch() / "fuzz.png";
  writeBytes(file, bytes);
  refusedCleanly([&] { io::readDepthPng(file.string(), fuzzLimits().maxGridCells); });
}

void colourImage(const std::string& bytes) {
  const bool jpeg = bytes.empty() || (bytes[0] & 1) == 0;
  const fs::path file = scratch() / (jpeg ? "fuzz.jpg" : "fuzz.png");
  writeBytes(file, bytes.empty() ? bytes : bytes.substr(1));
  refusedCleanly([&] { io::readColourImage(file.string(), fuzzLimits().maxGridCells); });
}

void depthSequence(const std::string& bytes) {
  const bool tum = bytes.empty() || (bytes[0] & 1) == 0;
  const fs::path dir = sequenceFolder(tum, parts(bytes.empty() ? bytes : bytes.substr(1)));
  io::ScanSourceOptions source;
  source.format = tum ? "tum" : "redwood";
  refusedCleanly([&] {
    for (const io::ConfScan& scan : io::readScanList(dir.string(), fuzzLimits(), source).scans)
      io::readScanGrid(scan, fuzzLimits());
  });
}

}  // namespace rangefuse::fuzz
