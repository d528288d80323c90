// The XDMF/HDF5 mesh holds the mesh the single-rank code builds, whatever the split of the
// bricks across ranks (some ranks writing nothing), in the layout h5py and ParaView read.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <fstream>

#include "SharedTemp.h"
#include "SphereField.h"
#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/mesh/PartStitching.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallelio/MeshPartXdmf.h"

using namespace rangefuse;
using namespace rangefuse::test;

namespace {

/// A whole 2-D dataset read on this rank alone: its dims, and its values as `T`.
template <class T>
std::vector<T> readDataset(const std::string& path, const char* name, hid_t type, hsize_t dims[2]) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(file, 0) << path;
  const hid_t set = H5Dopen2(file, name, H5P_DEFAULT);
  EXPECT_GE(set, 0) << name;
  const hid_t space = H5Dget_space(set);
  EXPECT_EQ(H5Sget_simple_extent_ndims(space), 2) << name;
  H5Sget_simple_extent_dims(space, dims, nullptr);
  std::vector<T> values(dims[0] * dims[1]);
  if (!values.empty()) H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Sclose(space);
  H5Dclose(set);
  H5Fclose(file);
  return values;
}

/// The single-rank mesh, as in DistributedMeshTest.
TriangleMesh serialSphereMesh() {
  BrickStore serial(sphereLayout(1), 0);
  fillSphere(serial);
  TriangleMesh one = extractDistributedMesh(serial, 0, MPI_COMM_SELF).mesh;
  one.normals = vertexNormals(one);
  return one;
}

void expectFileHolds(const std::string& xdmf, const TriangleMesh& want) {
  const std::string h5 = io::xdmfDataPath(xdmf);
  hsize_t dims[2] = {0, 0};
  const auto points = readDataset<double>(h5, "geometry", H5T_NATIVE_DOUBLE, dims);
  ASSERT_EQ(dims[0], want.vertices.size());
  ASSERT_EQ(dims[1], 3u);
  for (size_t i = 0; i < want.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(points[3 * i + k], want.vertices[i][k]) << i;
  const auto faces = readDataset<int64_t>(h5, "topology", H5T_NATIVE_INT64, dims);
  ASSERT_EQ(dims[0], want.faces.size());
  for (size_t f = 0; f < want.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(faces[3 * f + k], want.faces[f][k]) << f;
  const auto normals = readDataset<float>(h5, "normals", H5T_NATIVE_FLOAT, dims);
  ASSERT_EQ(dims[0], want.vertices.size());
  for (size_t i = 0; i < want.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(normals[3 * i + k], static_cast<float>(want.normals[i][k])) << i;
  std::ifstream in(xdmf);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string name = std::filesystem::path(h5).filename().string();
  EXPECT_NE(text.find("NumberOfElements=\"" + std::to_string(want.faces.size()) + "\""),
            std::string::npos);
  EXPECT_NE(text.find(name + ":/geometry"), std::string::npos) << text;
  EXPECT_NE(text.find(name + ":/topology"), std::string::npos) << text;
}

}  // namespace

TEST(MeshPartXdmf, HoldsTheSingleRankMeshWhateverTheSplit) {
  const std::string dir = test::sharedTempPath("part-xdmf");
  if (mpi::rank() == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  const TriangleMesh want = mpi::rank() == 0 ? serialSphereMesh() : TriangleMesh{};
  for (const std::string split : {"work", "first", "last"}) {
    BrickLayout layout = sphereLayout(mpi::size());
    const size_t n = layout.codes.size();
    std::vector<size_t> start = layout.rankStart;
    if (split == "first") std::fill(start.begin() + 1, start.end(), n);
    if (split == "last") std::fill(start.begin(), start.end() - 1, 0);
    layout.setRuns(start);
    BrickStore store(layout, mpi::rank());
    fillSphere(store);
    MeshPart part = extractDistributedMesh(store, 0, MPI_COMM_WORLD);
    addPartNormals(part, MPI_COMM_WORLD);
    const std::string path = dir + "/" + split + ".xdmf";
    ASSERT_TRUE(io::writeMeshPartXdmf(path, part, MPI_COMM_WORLD));
    if (mpi::rank() == 0) {
      SCOPED_TRACE(split);
      expectFileHolds(path, want);
      EXPECT_FALSE(std::filesystem::exists(io::xdmfDataPath(path) + ".tmp"));
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove_all(dir);
}

/// A colour that varies with position, so a vertex written in the wrong row shows.
Colour colourAt(const Eigen::Vector3d& p) {
  return Colour(0.5f + 0.4f * float(p.x()), 0.5f - 0.3f * float(p.y()),
                0.2f + float(p.z() * p.z()));
}

TEST(MeshPartXdmf, ColoursAndIntensitiesFollowTheirVertices) {
  const std::string dir = test::sharedTempPath("part-xdmf-colour");
  if (mpi::rank() == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  const TriangleMesh want = mpi::rank() == 0 ? serialSphereMesh() : TriangleMesh{};
  for (const ColourKind kind : {ColourKind::rgb, ColourKind::intensity}) {
    BrickStore store(sphereLayout(mpi::size()), mpi::rank());
    fillSphere(store);
    MeshPart part = extractDistributedMesh(store, 0, MPI_COMM_WORLD);
    part.colour = kind;
    for (const auto& v : part.mesh.vertices) part.mesh.colours.push_back(colourAt(v));
    const std::string path = dir + "/" + colourKindName(kind) + ".xdmf";
    ASSERT_TRUE(io::writeMeshPartXdmf(path, part, MPI_COMM_WORLD));
    if (mpi::rank() != 0) continue;
    SCOPED_TRACE(colourKindName(kind));
    hsize_t dims[2] = {0, 0};
    const std::string h5 = io::xdmfDataPath(path);
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (kind == ColourKind::rgb) {
      const auto bytes = readDataset<uint8_t>(h5, "colours", H5T_NATIVE_UINT8, dims);
      ASSERT_EQ(dims[0], want.vertices.size());
      ASSERT_EQ(dims[1], 3u);
      for (size_t i = 0; i < want.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k)
          ASSERT_EQ(bytes[3 * i + k], colourByte(colourAt(want.vertices[i])[k])) << i;
      EXPECT_NE(text.find("Name=\"Colour\" AttributeType=\"Vector\""), std::string::npos) << text;
      EXPECT_NE(text.find("NumberType=\"UChar\" Precision=\"1\""), std::string::npos) << text;
    } else {
      const auto values = readDataset<float>(h5, "colours", H5T_NATIVE_FLOAT, dims);
      ASSERT_EQ(dims[0], want.vertices.size());
      ASSERT_EQ(dims[1], 1u);
      for (size_t i = 0; i < want.vertices.size(); ++i)
        ASSERT_EQ(values[i], colourAt(want.vertices[i])[0]) << i;
      EXPECT_NE(text.find("Name=\"Intensity\" AttributeType=\"Scalar\""), std::string::npos)
          << text;
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove_all(dir);
}

TEST(MeshPartXdmf, AnUnwritableFolderFailsOnEveryRankWithoutAFile) {
  const std::string dir = test::sharedTempPath("xdmf-missing-folder");
  MeshPart part;
  part.rank = mpi::rank();
  const std::string path = dir + "/no/such/mesh.xdmf";
  EXPECT_FALSE(io::writeMeshPartXdmf(path, part, MPI_COMM_WORLD));
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(io::xdmfDataPath(path) + ".tmp"));
}
