// Indexed triangle mesh.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

namespace rangefuse {

using Triangle = std::array<int32_t, 3>;

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Triangle> faces;
  std::vector<Eigen::Vector3d> normals;  ///< empty, or one per vertex
  std::vector<Eigen::Vector3f> colours;  ///< empty, or one per vertex (channels in [0, 1])
  /// Empty, or one per vertex: 1 where the vertex closes a hole no scan saw (--fill-holes).
  std::vector<uint8_t> filled;
};

}  // namespace rangefuse
