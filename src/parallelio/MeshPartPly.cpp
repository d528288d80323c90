#include "rangefuse/parallelio/MeshPartPly.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>

#include "FailedTemporary.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/io/PlyMeshFormat.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::io {
namespace {

/// Header fields agreed by all ranks: the same reductions writeMeshPly makes on one rank.
internal::PlyMeshFormat formatOf(const MeshPart& part, MPI_Comm comm) {
  double mine = 0, maxAbs = 0;
  for (const auto& v : part.mesh.vertices) mine = std::max(mine, v.cwiseAbs().maxCoeff());
  MPI_Allreduce(&mine, &maxAbs, 1, MPI_DOUBLE, MPI_MAX, comm);
  const double step = internal::floatStep(maxAbs);
  int64_t edges = 0, allEdges = 0;
  const auto& v = part.mesh.vertices;
  for (const auto& t : part.mesh.faces) edges += internal::edgeUnits(v[t[0]], v[t[1]], step);
  MPI_Allreduce(&edges, &allEdges, 1, MPI_INT64_T, MPI_SUM, comm);
  int normals = !part.mesh.normals.empty(), allNormals = 0;
  MPI_Allreduce(&normals, &allNormals, 1, MPI_INT, MPI_MAX, comm);
  internal::PlyMeshFormat f;
  f.vertices = part.totalVertices;
  f.faces = part.totalFaces;
  f.wide = internal::needsDoubleVertices(maxAbs, allEdges, f.faces);
  f.normals = allNormals;
  f.colour = part.colour;
  f.filled = part.marksFilled;
  return f;
}

std::string encodeVertices(const MeshPart& part, const internal::PlyMeshFormat& f) {
  std::string out;
  out.reserve(part.ownedVertices * f.vertexBytes());
  for (size_t i = 0; i < part.mesh.vertices.size(); ++i)
    if (part.owns(i))
      internal::encodeVertex(out, f, part.mesh.vertices[i],
                             f.normals ? &part.mesh.normals[i] : nullptr,
                             f.colour != ColourKind::none ? &part.mesh.colours[i] : nullptr,
                             f.filled ? part.mesh.filled[i] : 0);
  return out;
}

std::string encodeFaces(const MeshPart& part) {
  std::string out;
  out.reserve(part.mesh.faces.size() * internal::PlyMeshFormat::kFaceBytes);
  const auto& g = part.global;
  for (const auto& t : part.mesh.faces)
    internal::encodeFace(out, static_cast<int32_t>(g[t[0]]), static_cast<int32_t>(g[t[1]]),
                         static_cast<int32_t>(g[t[2]]));
  return out;
}

/// Creates (or empties) the temporary on rank 0 alone, so that a missing folder or a
/// read-only one is one clear message before any rank opens it.
void createEmpty(const std::string& tmp, const std::string& path) {
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) throw InputError(path + ": cannot open for writing: " + std::strerror(errno));
  ::close(fd);
}

void checkMpiIo(int rc, const std::string& path, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(rc, text, &length);
  throw InputError(path + ": " + what + " failed: " + std::string(text, length));
}

/// Writes bytes at offset in pieces a signed int can count.
void writeAt(MPI_File file, MPI_Offset offset, const std::string& bytes, const std::string& path) {
  const size_t chunk = std::numeric_limits<int>::max() / 2;
  for (size_t done = 0; done < bytes.size();) {
    const int n = static_cast<int>(std::min(chunk, bytes.size() - done));
    MPI_Status status;
    checkMpiIo(MPI_File_write_at(file, offset + static_cast<MPI_Offset>(done), bytes.data() + done,
                                 n, MPI_CHAR, &status),
               path, "write");
    int written = 0;
    MPI_Get_count(&status, MPI_CHAR, &written);
    if (written != n)
      throw InputError(path + ": short write: the disk is full? (" +
                       std::to_string(std::max<int64_t>(0, freeBytes(path)) >> 20) +
                       " MiB free there)");
    done += static_cast<size_t>(n);
  }
}

/// This rank's blocks, through its own MPI-IO handle: each rank's part is two contiguous
/// blocks, so collective buffering has nothing to gain, and a rank whose write fails must not
/// leave the others in a collective close (docs/decisions.md).
void writeBlocks(const std::string& tmp, const std::string& path,
                 const std::vector<std::pair<MPI_Offset, std::string>>& blocks) {
  MPI_File file;
  checkMpiIo(MPI_File_open(MPI_COMM_SELF, tmp.c_str(), MPI_MODE_WRONLY, MPI_INFO_NULL, &file), path,
             "open");
  try {
    faultPoint("write", path);
    for (const auto& [offset, bytes] : blocks) writeAt(file, offset, bytes, path);
    checkMpiIo(MPI_File_sync(file), path, "sync");
  } catch (...) {
    MPI_File_close(&file);
    throw;
  }
  checkMpiIo(MPI_File_close(&file), path, "close");
}

}  // namespace

bool writeMeshPartPly(const std::string& path, const MeshPart& part, MPI_Comm comm) {
  const std::string tmp = temporaryPath(path);
  const bool root = mpi::rank(comm) == 0;
  internal::PlyMeshFormat f;
  std::vector<std::pair<MPI_Offset, std::string>> blocks;
  const bool ok = mpi::collectively(comm, [&] {
    if (part.totalVertices > static_cast<uint64_t>(std::numeric_limits<int32_t>::max()))
      throw InputError(path + ": " + std::to_string(part.totalVertices) +
                       " vertices: more than a PLY int index can address");
    f = formatOf(part, comm);
    const std::string header = f.header();
    const MPI_Offset faces0 = static_cast<MPI_Offset>(header.size() + f.vertices * f.vertexBytes());
    if (root) blocks.emplace_back(0, header);
    blocks.emplace_back(header.size() + part.firstVertex * f.vertexBytes(),
                        encodeVertices(part, f));
    blocks.emplace_back(faces0 + part.firstFace * f.kFaceBytes, encodeFaces(part));
    if (root) createEmpty(tmp, path);
  });
  if (!ok) return false;
  if (!mpi::collectively(comm, [&] { writeBlocks(tmp, path, blocks); })) {
    if (root) internal::removeFailedTemporary(tmp);
    return false;
  }
  return mpi::collectively(comm, [&] {
    if (root && std::rename(tmp.c_str(), path.c_str()) != 0) {
      const std::string cause = std::strerror(errno);
      std::remove(tmp.c_str());
      throw InputError(path + ": cannot rename the temporary file into place: " + cause);
    }
  });
}

}  // namespace rangefuse::io
