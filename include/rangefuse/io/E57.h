// ASTM E2807 (E57) files, the exchange format of terrestrial laser scanners, read from the
// standard: a 48-byte header, 1024-byte pages each ending in a CRC-32C of its other 1020 bytes,
// an XML tree naming each scan (`data3D`) with its pose and the prototype of its point records,
// and per scan a compressed vector: data packets holding one byte stream per prototype field,
// bit-packed. A file is indexed once (header and XML); each scan's points are then decoded on
// their own, page by page, never the whole file at once. Images (`images2D`) are ignored.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::io {

/// One field of a scan's point records, as its prototype describes it.
struct E57Field {
  enum class Kind { integer, scaledInteger, single, double_ };
  std::string name;  ///< the prototype element's name, e.g. "cartesianX"
  Kind kind = Kind::integer;
  int64_t minimum = 0, maximum = 0;  ///< integers: the raw values' bounds
  double scale = 1, offset = 0;      ///< scaled integers: value = raw · scale + offset

  /// Bits a value takes in the bit-pack codec (0 for an integer whose bounds are equal).
  int bits() const;
};

/// Where one scan of an E57 file lies and how it is placed.
struct E57Scan {
  std::string name, guid;
  Pose pose;                     ///< scan frame to the file's frame
  uint64_t records = 0;          ///< point records
  uint64_t section = 0;          ///< physical offset of the points' compressed vector section
  std::vector<E57Field> fields;  ///< the prototype's fields, in byte-stream order
  bool spherical = false;        ///< coordinates as range, azimuth, elevation (else cartesian)
  /// Rows and columns of a structured scan (rowIndex and columnIndex in the prototype); 0 when
  /// the scan has none.
  int rows = 0, cols = 0;
  int64_t firstRow = 0, firstColumn = 0;      ///< the indices' smallest values
  double intensityMin = 0, intensityMax = 1;  ///< intensityLimits, else the field's bounds
  double colourMin = 0, colourMax = 255;      ///< colorLimits (red), else the field's bounds
  bool intensity = false;  ///< read the intensity even where colour is given (--colour intensity)
};

/// The scans of an E57 file: header, page checksums of the XML and the XML tree checked, no
/// point read. Throws InputError naming the file and what is wrong (for binary damage the page
/// and byte offset): a bad signature, version or page size, a length that disagrees with the
/// file, a malformed or unexpected XML tree, an unknown codec, a prototype without coordinates,
/// a structured grid larger than `limits`.
std::vector<E57Scan> indexE57(const std::string& path, const InputLimits& limits = {});

/// Reads one scan as a spherical grid with the station at the scan frame's origin, like a PTX
/// station: row and column from rowIndex and columnIndex, invalid or missing records as empty
/// cells, each point coloured by colorRed/Green/Blue (rgb) or else intensity, normalised by the
/// limits. A scan without indices is gridded by spherical projection around its origin, the
/// angular step estimated from the data (`warning` says so). Every page read is checked.
RangeGrid readE57Scan(const std::string& path, const E57Scan& scan, std::string* warning = nullptr);

/// Columns [first, first + count) of a structured scan as a spherical grid of `count` columns:
/// the records are decoded in one pass and only those columns kept.
RangeGrid readE57Columns(const std::string& path, const E57Scan& scan, int first, int count);

/// How writeE57 stores coordinates.
enum class E57Coordinates { cartesianSingle, cartesianDouble, cartesianScaled, sphericalDouble };

struct E57Writing {
  E57Coordinates coordinates = E57Coordinates::cartesianDouble;
  double scaledStep = 1e-4;   ///< cartesianScaled: the integer step, in scan units
  bool structured = true;     ///< rowIndex, columnIndex and every cell (empty ones invalid)
  int packetRecords = 0;      ///< records a data packet at most (0: fill packets to 64 KiB)
  bool intensityToo = false;  ///< rgb stations: an intensity field as well (the colour's mean)
};

/// Writes stations (spherical grids with their poses) as one E57 file, one data3D scan each,
/// colours as colorRed/Green/Blue (rgb) or intensity. Atomic. For tests and synthetic data.
void writeE57(const std::string& path, const std::vector<RangeGrid>& grids,
              const std::vector<Pose>& poses, const E57Writing& how = {});

}  // namespace rangefuse::io
