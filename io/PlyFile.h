// Generic PLY reading shared by the range-grid and mesh readers (private to io/).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace rangefuse::io::internal {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };
enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  ///< value type (of the items, for a list)
  bool isList = false;
  PlyType countType = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

/// One element's values: scalars row-major (count x scalar properties); each list
/// property flattened with offsets.
struct PlyElementData {
  PlyElement element;
  std::vector<std::string> scalarNames;
  std::vector<double> scalars;
  std::vector<std::string> listNames;
  std::vector<std::vector<uint32_t>> listOffsets;  ///< per list: count+1 offsets
  std::vector<std::vector<int64_t>> listValues;    ///< per list: flattened items

  /// Column of scalar property `name`, or -1.
  int scalarColumn(const std::string& name) const;
  /// Index of list property `name`, or -1.
  int listIndex(const std::string& name) const;
  double scalar(uint64_t item, int column) const {
    return scalars[item * scalarNames.size() + column];
  }
};

struct PlyFile {
  std::string path;
  PlyFormat format = PlyFormat::Ascii;
  std::map<std::string, std::string> objInfo;  ///< obj_info KEY VALUE lines
  std::vector<PlyElementData> elements;

  /// The element called `name`, or nullptr.
  const PlyElementData* find(const std::string& name) const;
};

/// Bytes a binary value of type t takes.
size_t typeSize(PlyType t);

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::map<std::string, std::string> objInfo;
  std::vector<PlyElement> elements;
  size_t bodyOffset = 0;  ///< where the body starts
  int lines = 0;          ///< lines in the header
};

/// A whole file's bytes, read with one allocation (not zeroed first) and large reads.
class FileBytes {
 public:
  /// Throws InputError naming the file if it cannot be opened or read.
  explicit FileBytes(const std::string& path);
  std::string_view view() const { return {bytes_.get(), size_}; }

 private:
  std::unique_ptr<char[]> bytes_;
  size_t size_ = 0;
};

/// The header of PLY bytes; throws InputError naming `path` and the line.
PlyHeader parsePlyHeader(const std::string& path, std::string_view text);

/// Refuses element counts above maxElements, or more than a body of `bytes` (the whole
/// file's) can hold, before anything is allocated for them.
void checkPlyCounts(const std::string& path, const PlyHeader& h, size_t bytes,
                    uint64_t maxElements);

/// Parses PLY bytes; `name` (the file) heads every message. Element counts above
/// maxElements are refused before anything is allocated for them.
PlyFile parsePly(const std::string& name, std::string_view text, uint64_t maxElements);

/// Reads a whole PLY file; throws InputError naming the file and line or element.
PlyFile readPly(const std::string& path, uint64_t maxElements);

}  // namespace rangefuse::io::internal
