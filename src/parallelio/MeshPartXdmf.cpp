#include "rangefuse/parallelio/MeshPartXdmf.h"

#include <cstdio>
#include <filesystem>

#include "Hdf5Writing.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::io {
namespace {

using internal::createDataset;
using internal::Handle;
using internal::together;
using internal::writeRows;

struct OwnedRows {
  std::vector<double> points;
  std::vector<float> normals;
  std::vector<uint8_t> rgb;      ///< 3 bytes a vertex, when the part is coloured
  std::vector<float> intensity;  ///< 1 float a vertex, when it carries intensity
  std::vector<uint8_t> filled;   ///< 1 byte a vertex, when it marks filled vertices
  std::vector<int64_t> faces;
};

/// The columns and HDF5 type of the /colours dataset for `kind`.
hsize_t colourColumns(ColourKind kind) {
  return kind == ColourKind::rgb ? 3 : 1;
}
hid_t colourType(ColourKind kind) {
  return kind == ColourKind::rgb ? H5T_NATIVE_UINT8 : H5T_NATIVE_FLOAT;
}

void addColour(OwnedRows& rows, ColourKind kind, const Colour& c) {
  if (kind == ColourKind::rgb)
    for (int k = 0; k < 3; ++k) rows.rgb.push_back(colourByte(c[k]));
  if (kind == ColourKind::intensity) rows.intensity.push_back(c[0]);
}

/// This rank's rows, in file order: owned vertices by first use, then its faces.
OwnedRows ownedRows(const MeshPart& part) {
  OwnedRows rows;
  const auto& m = part.mesh;
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    if (!part.owns(i)) continue;
    for (int k = 0; k < 3; ++k) rows.points.push_back(m.vertices[i][k]);
    if (!m.normals.empty())
      for (int k = 0; k < 3; ++k) rows.normals.push_back(static_cast<float>(m.normals[i][k]));
    if (part.colour != ColourKind::none) addColour(rows, part.colour, m.colours[i]);
    if (part.marksFilled) rows.filled.push_back(m.filled[i]);
  }
  for (const auto& t : m.faces)
    for (int k = 0; k < 3; ++k) rows.faces.push_back(part.global[t[k]]);
  return rows;
}

void writeData(const std::string& tmp, const MeshPart& part, bool normals, MPI_Comm comm) {
  const OwnedRows rows = ownedRows(part);
  Handle fapl = internal::accessList(comm);
  errno = 0;
  Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose);
  together(file.ok(), tmp, "cannot create the mesh data file", comm);
  {
    Handle set =
        createDataset(file, "geometry", H5T_NATIVE_DOUBLE, part.totalVertices, 3, tmp, comm);
    writeRows(set, H5T_NATIVE_DOUBLE, part.firstVertex, part.ownedVertices, 3, rows.points.data(),
              tmp, "geometry", comm);
  }
  {
    Handle set = createDataset(file, "topology", H5T_NATIVE_INT64, part.totalFaces, 3, tmp, comm);
    writeRows(set, H5T_NATIVE_INT64, part.firstFace, part.mesh.faces.size(), 3, rows.faces.data(),
              tmp, "topology", comm);
  }
  if (normals) {
    Handle set = createDataset(file, "normals", H5T_NATIVE_FLOAT, part.totalVertices, 3, tmp, comm);
    writeRows(set, H5T_NATIVE_FLOAT, part.firstVertex, part.ownedVertices, 3, rows.normals.data(),
              tmp, "normals", comm);
  }
  if (part.colour != ColourKind::none) {
    const hsize_t cols = colourColumns(part.colour);
    const hid_t type = colourType(part.colour);
    const void* data = part.colour == ColourKind::rgb ? static_cast<const void*>(rows.rgb.data())
                                                      : rows.intensity.data();
    Handle set = createDataset(file, "colours", type, part.totalVertices, cols, tmp, comm);
    writeRows(set, type, part.firstVertex, part.ownedVertices, cols, data, tmp, "colours", comm);
  }
  if (part.marksFilled) {
    Handle set = createDataset(file, "filled", H5T_NATIVE_UINT8, part.totalVertices, 1, tmp, comm);
    writeRows(set, H5T_NATIVE_UINT8, part.firstVertex, part.ownedVertices, 1, rows.filled.data(),
              tmp, "filled", comm);
  }
  errno = 0;
  together(file.close() >= 0, tmp, "cannot finish writing (flush and close)", comm);
}

void dataItem(std::ostream& out, uint64_t rows, const char* type, int bytes,
              const std::string& file, const char* set, int cols = 3) {
  out << "        <DataItem Dimensions=\"" << rows << " " << cols << "\" NumberType=\"" << type
      << "\" Precision=\"" << bytes << "\" Format=\"HDF\">" << file << ":/" << set
      << "</DataItem>\n";
}

void writeDescription(std::ostream& out, const MeshPart& part, bool normals,
                      const std::string& dataFile) {
  out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
      << "    <Grid Name=\"rangefuse\" GridType=\"Uniform\">\n"
      << "      <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << part.totalFaces
      << "\">\n";
  dataItem(out, part.totalFaces, "Int", 8, dataFile, "topology");
  out << "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n";
  dataItem(out, part.totalVertices, "Float", 8, dataFile, "geometry");
  out << "      </Geometry>\n";
  if (normals) {
    out << "      <Attribute Name=\"Normals\" AttributeType=\"Vector\" Center=\"Node\">\n";
    dataItem(out, part.totalVertices, "Float", 4, dataFile, "normals");
    out << "      </Attribute>\n";
  }
  if (part.colour == ColourKind::rgb) {
    // Unsigned bytes, so ParaView can show them as colours with "Map Scalars" off.
    out << "      <Attribute Name=\"Colour\" AttributeType=\"Vector\" Center=\"Node\">\n";
    dataItem(out, part.totalVertices, "UChar", 1, dataFile, "colours");
    out << "      </Attribute>\n";
  }
  if (part.colour == ColourKind::intensity) {
    out << "      <Attribute Name=\"Intensity\" AttributeType=\"Scalar\" Center=\"Node\">\n";
    dataItem(out, part.totalVertices, "Float", 4, dataFile, "colours", 1);
    out << "      </Attribute>\n";
  }
  if (part.marksFilled) {  // 1 on the vertices that close a hole (--fill-holes)
    out << "      <Attribute Name=\"Filled\" AttributeType=\"Scalar\" Center=\"Node\">\n";
    dataItem(out, part.totalVertices, "UChar", 1, dataFile, "filled", 1);
    out << "      </Attribute>\n";
  }
  out << "    </Grid>\n  </Domain>\n</Xdmf>\n";
}

}  // namespace

bool isXdmfPath(const std::string& path) {
  return std::filesystem::path(path).extension() == ".xdmf";
}

std::string xdmfDataPath(const std::string& xdmfPath) {
  return std::filesystem::path(xdmfPath).replace_extension(".h5").string();
}

bool writeMeshPartXdmf(const std::string& path, const MeshPart& part, MPI_Comm comm) {
  const std::string data = xdmfDataPath(path), tmp = temporaryPath(data);
  int normals = !part.mesh.normals.empty();
  MPI_Allreduce(MPI_IN_PLACE, &normals, 1, MPI_INT, MPI_MAX, comm);
  const std::string cause =
      internal::agreeOnWrite(tmp, comm, [&] { writeData(tmp, part, normals, comm); });
  if (!mpi::agree(cause.empty(), cause, comm)) return false;
  const bool root = mpi::rank(comm) == 0;
  const std::string dataName = std::filesystem::path(data).filename().string();
  const bool described = mpi::collectively(comm, [&] {
    if (root)
      writeAtomically(path,
                      [&](std::ostream& out) { writeDescription(out, part, normals, dataName); });
  });
  if (!described) {
    if (root) std::remove(tmp.c_str());
    return false;
  }
  return mpi::collectively(comm, [&] {
    try {
      internal::renameIntoPlace(tmp, data, comm);
    } catch (...) {
      if (root) std::remove(path.c_str()), std::remove(tmp.c_str());
      throw;
    }
  });
}

}  // namespace rangefuse::io
