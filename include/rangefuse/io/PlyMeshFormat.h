// Byte layout of the binary mesh PLY that both mesh writers produce, so that one rank's file
// and many ranks' file are the same bytes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "rangefuse/core/Colour.h"

namespace rangefuse::io::internal {

/// What decides the header and the size of every record.
struct PlyMeshFormat {
  uint64_t vertices = 0;
  uint64_t faces = 0;
  bool wide = false;  ///< double vertex coordinates instead of float
  bool normals = false;
  ColourKind colour = ColourKind::none;  ///< rgb: uchar red green blue; intensity: a float
  bool filled = false;                   ///< uchar filled: 1 on vertices that close a hole

  std::string header() const;
  size_t vertexBytes() const {
    return (wide ? 24 : 12) + (normals ? 12 : 0) +
           (colour == ColourKind::rgb         ? 3
            : colour == ColourKind::intensity ? 4
                                              : 0) +
           (filled ? 1 : 0);
  }
  static constexpr size_t kFaceBytes = 13;  // uchar count + 3 int indices
};

/// A float's step at the largest coordinate magnitude.
double floatStep(double maxAbs);

/// One face's edge length in 1/16 of a float step, an integer so that sums over ranks are
/// exact in any order. Edges within the bounding box stay below 2^29 units.
int64_t edgeUnits(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step);

/// Float vertices keep files small, but far from the origin (a survey's coordinates with
/// millimetre voxels) a float's step would be a sizeable part of an edge: then doubles, when
/// the step exceeds 1/1000 of the mean edge.
bool needsDoubleVertices(double maxAbs, int64_t edgeUnitsSum, uint64_t faces);

/// Appends one vertex record (normal and colour may be null when the format has none; `filled`
/// is written when the format has it).
void encodeVertex(std::string& out, const PlyMeshFormat& f, const Eigen::Vector3d& p,
                  const Eigen::Vector3d* normal, const Colour* colour = nullptr,
                  uint8_t filled = 0);

/// Appends one triangle record.
void encodeFace(std::string& out, int32_t a, int32_t b, int32_t c);

}  // namespace rangefuse::io::internal
