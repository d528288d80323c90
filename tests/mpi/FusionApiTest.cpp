// The library's API (rangefuse/rangefuse.h) against the command: the same scans handed over in
// memory give the command's mesh; bad input throws the command's kind of message on every rank.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "SharedTemp.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallelio/Checkpoint.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/rangefuse.h"
#include "rangefuse/run/FuseJob.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;
using test::sharedTempPath;

namespace {

constexpr double kApiVoxel = 0.002;  // 2 mm: the bunny in a second

/// The bunny's scans, read as the command reads them, added to a fusion on `comm`.
TriangleMesh bunnyThroughTheApi(MPI_Comm comm) {
  FieldSettings field;
  field.voxel = kApiVoxel;
  Fusion fusion(field, comm);
  for (const io::ConfScan& c : io::readConf(RANGEFUSE_TEST_DATA "/bunny/bun.conf").scans)
    fusion.addGrid(io::readRangeGridPly(c.path), c.pose, c.name);
  EXPECT_EQ(fusion.frames(), 10u);
  return fusion.mesh();
}

/// What a throwing call said, on this rank ("" when it did not throw).
template <class Fn>
std::string messageOf(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

Pose turned(double degrees) {
  Pose p;
  p.R = Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return p;
}

/// The first frames of a hand-held camera's depth frames of the bunny scaled to 1.5 m (160 x 120,
/// noise growing with depth), and the frames' true camera poses.
struct HandheldFrames {
  std::vector<io::DepthImage> depth;
  std::vector<Pose> truth;
  io::DepthCamera camera;
};

HandheldFrames handheldFrames(int views, size_t first) {
  TriangleMesh bunny = io::readMeshPly(RANGEFUSE_TEST_DATA "/bunny/bun_zipper.ply");
  for (Eigen::Vector3d& v : bunny.vertices) v *= 10;
  ScanSettings s;
  s.views = views, s.width = 160, s.height = 120, s.voxel = 0.01, s.noise = 0.5;
  s.depthNoise = true, s.path = ViewPath::Handheld;
  HandheldFrames out;
  const SyntheticSet set = scanMesh(bunny, s);
  for (size_t i = 0; i < first; ++i) {
    const SyntheticScan& sc = set.scans[i];
    out.depth.push_back(io::depthImage(sc.grid, 1e-3));
    out.truth.push_back(io::cameraPose(sc.truth));
    out.camera = io::depthCamera(sc.grid, 1e-3);
  }
  return out;
}

/// Every frame tracked on `comm`: their camera poses and the mesh.
std::pair<std::vector<Pose>, TriangleMesh> tracked(const HandheldFrames& frames, MPI_Comm comm) {
  FieldSettings field;
  field.voxel = 0.01;
  Fusion fusion(field, comm);
  std::vector<Pose> poses;
  for (const io::DepthImage& d : frames.depth) {
    const TrackedFrame r = fusion.track(d, frames.camera);
    EXPECT_TRUE(r.fused) << poses.size() << ": " << r.why;
    poses.push_back(r.cameraToWorld);
  }
  // The frames' images are let go of once tracked; their content hashes were kept.
  // One file per fusion: on MPI_COMM_SELF every rank writes its own.
  const int writer = comm == MPI_COMM_SELF ? mpi::rank() : 0;
  const std::string checkpoint =
      test::sharedTempPath("api-tracked") + "-" + std::to_string(writer) + ".h5";
  fusion.saveCheckpoint(checkpoint);
  const io::CheckpointMeta meta = io::readCheckpointMeta(checkpoint, comm);
  EXPECT_EQ(std::set<std::string>(meta.scanHashes.begin(), meta.scanHashes.end()).size(),
            frames.depth.size());
  MPI_Barrier(comm);
  if (mpi::rank(comm) == 0) std::filesystem::remove(checkpoint);
  return {poses, fusion.mesh()};
}

}  // namespace

TEST(FusionApi, TracksAStreamTheSameOnAnyRankCountAndCloseToTheTruth) {
  const HandheldFrames frames = handheldFrames(240, 30);  // the first eighth of the path
  const auto [both, bothMesh] = tracked(frames, MPI_COMM_WORLD);
  const auto [alone, aloneMesh] = tracked(frames, MPI_COMM_SELF);
  double sum = 0;
  const Pose first = frames.truth[0].inverse();
  for (size_t i = 0; i < both.size(); ++i) {
    ASSERT_EQ(both[i].R, alone[i].R) << i;
    ASSERT_EQ(both[i].t, alone[i].t) << i;
    sum += (first.apply(frames.truth[i].t) - both[i].t).squaredNorm();
  }
  const double ate = std::sqrt(sum / both.size());
  std::printf("API tracking, 30 frames: ATE %.4f m\n", ate);
  EXPECT_LT(ate, 0.006);  // the command's bound on its stream (0.6 voxel)
  if (mpi::rank() != 0) return;
  ASSERT_GT(bothMesh.faces.size(), 1000u);
  EXPECT_EQ(bothMesh.faces, aloneMesh.faces);
  EXPECT_EQ(bothMesh.vertices, aloneMesh.vertices);
}

TEST(FusionApi, FusesTheBunnyToTheCommandsMeshOnAnyRankCount) {
  FuseOptions o;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.field.voxel = kApiVoxel;
  o.quiet = true;
  o.outputs.out = sharedTempPath("api-bunny.ply");
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  const TriangleMesh both = bunnyThroughTheApi(MPI_COMM_WORLD);
  const TriangleMesh alone = bunnyThroughTheApi(MPI_COMM_SELF);
  if (mpi::rank() != 0) {
    EXPECT_TRUE(both.vertices.empty());
    return;
  }
  const TriangleMesh command = io::readMeshPly(o.outputs.out);
  std::filesystem::remove(o.outputs.out);
  ASSERT_GT(command.faces.size(), 10000u);
  ASSERT_EQ(both.vertices.size(), command.vertices.size());
  EXPECT_EQ(both.faces, command.faces);
  EXPECT_EQ(both.vertices, alone.vertices);  // bit for bit on one rank and on all
  EXPECT_EQ(both.faces, alone.faces);
  EXPECT_EQ(both.normals.size(), both.vertices.size());
  for (size_t i = 0; i < both.vertices.size(); ++i)  // the PLY holds floats
    ASSERT_EQ(both.vertices[i].cast<float>(), command.vertices[i].cast<float>()) << i;
}

TEST(FusionApi, DepthImagesOfAWallGiveItsPlaneAndColour) {
  FieldSettings field;
  field.voxel = 0.01;
  Fusion fusion(field, MPI_COMM_WORLD);
  io::DepthCamera camera{100, 100, 39.5, 29.5, 80, 60, 1e-3, 0};
  io::DepthImage depth{80, 60, std::vector<uint16_t>(80 * 60, 2000)};  // 2 m ahead
  Image colour(80, 60, 0);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x) colour.set(x, y, 200, 100, 50);
  // The plane z = 2 seen by cameras at the origin turned about y: pixel ray (x, y, 1) meets it
  // at camera depth 2 / (cos a - x sin a).
  for (const double deg : {-10.0, 0.0, 10.0}) {
    io::DepthImage d = depth;
    for (int u = 0; u < 80; ++u) {
      const double x = (u - camera.cx) / camera.fx, a = deg * M_PI / 180;
      const double z = 2.0 / (std::cos(a) - x * std::sin(a));
      for (int v = 0; v < 60; ++v) d.counts[v * 80 + u] = static_cast<uint16_t>(z * 1000 + 0.5);
    }
    fusion.addDepth(d, camera, turned(deg), &colour);
  }
  const TriangleMesh mesh = fusion.mesh();
  if (mpi::rank() != 0) return;
  ASSERT_GT(mesh.vertices.size(), 100u);
  ASSERT_EQ(mesh.colours.size(), mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    ASSERT_NEAR(mesh.vertices[i].z(), 2.0, 0.5 * field.voxel) << i;
    ASSERT_NEAR(mesh.colours[i].x(), 200 / 255.0, 0.01) << i;
    ASSERT_NEAR(mesh.colours[i].z(), 50 / 255.0, 0.01) << i;
  }
}

TEST(FusionApi, BadInputThrowsTheCommandsMessageOnEveryRank) {
  FieldSettings field;
  EXPECT_NE(messageOf([&] { Fusion f(field, MPI_COMM_WORLD); }).find("voxel"), std::string::npos);
  field.voxel = 0.002;
  Fusion fusion(field, MPI_COMM_WORLD);
  EXPECT_EQ(messageOf([&] { fusion.meshPart(); }), "Fusion: no frames to fuse");
  RangeGrid grid = io::readRangeGridPly(RANGEFUSE_TEST_DATA "/bunny/bun000.ply");
  Pose bad;
  bad.t.x() = NAN;
  EXPECT_EQ(messageOf([&] { fusion.addGrid(grid, bad, "front"); }),
            "front: the pose is not finite");
  RangeGrid broken = grid;
  broken.cell[7] = static_cast<int32_t>(grid.points.size());
  EXPECT_NE(messageOf([&] { fusion.addGrid(broken, Pose{}); }).find("frame_0: a cell names point"),
            std::string::npos);
  EXPECT_EQ(fusion.frames(), 0u);
  // A failure inside the collective stages: every rank gets the message one rank printed.
  field.maxVoxels = 1000;
  Fusion tiny(field, MPI_COMM_WORLD);
  tiny.addGrid(grid, Pose{});
  const std::string message = messageOf([&] { tiny.mesh(); });
  EXPECT_NE(message.find("voxels"), std::string::npos) << message;
}

TEST(FusionApi, CheckpointsResumeToTheSameMeshEitherWay) {
  const std::string mine = sharedTempPath("api-fusion.h5"), theirs = sharedTempPath("api-cmd.h5");
  FieldSettings field;
  field.voxel = kApiVoxel;
  Fusion fusion(field, MPI_COMM_WORLD);
  for (const io::ConfScan& c : io::readConf(RANGEFUSE_TEST_DATA "/bunny/bun.conf").scans)
    fusion.addGrid(io::readRangeGridPly(c.path), c.pose, c.name);
  fusion.saveCheckpoint(mine);
  const TriangleMesh fused = fusion.mesh();
  // Resumed on the other rank count: the same mesh, and no more frames.
  Fusion resumed = Fusion::resume(mine, MPI_COMM_SELF);
  EXPECT_EQ(resumed.frames(), 10u);
  const TriangleMesh again = resumed.mesh();
  RangeGrid grid = io::readRangeGridPly(RANGEFUSE_TEST_DATA "/bunny/bun000.ply");
  EXPECT_NE(messageOf([&] { resumed.addGrid(grid, Pose{}); }).find("finished field"),
            std::string::npos);
  // The command's checkpoint of the same scans resumes through the API to the command's mesh.
  FuseOptions o;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.field.voxel = kApiVoxel;
  o.quiet = true;
  o.outputs.out = sharedTempPath("api-cmd.ply");
  o.outputs.checkpoint = theirs;
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  const TriangleMesh command = Fusion::resume(theirs, MPI_COMM_WORLD).mesh();
  EXPECT_EQ(messageOf([&] { Fusion::resume(o.outputs.out, MPI_COMM_WORLD); }).find(o.outputs.out),
            0u);
  if (mpi::rank() != 0) return;
  for (const std::string& p : {mine, theirs, o.outputs.out}) std::filesystem::remove(p);
  ASSERT_GT(fused.faces.size(), 10000u);
  EXPECT_EQ(again.faces, fused.faces);
  EXPECT_EQ(again.vertices, fused.vertices);
  EXPECT_EQ(command.faces, fused.faces);
  EXPECT_EQ(command.vertices, fused.vertices);
}

TEST(FusionApi, ScansAddedByTheirListAreTheGridsAddedAndHashedAsTheCommandHashesThem) {
  const std::string conf = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  FieldSettings field;
  field.voxel = kApiVoxel;
  Fusion fusion(field, MPI_COMM_WORLD);
  fusion.addScans(conf);
  EXPECT_EQ(fusion.frames(), 10u);
  const std::string checkpoint = sharedTempPath("api-scans.h5");
  fusion.saveCheckpoint(checkpoint);
  const io::CheckpointMeta meta = io::readCheckpointMeta(checkpoint, MPI_COMM_WORLD);
  const TriangleMesh listed = fusion.mesh(), added = bunnyThroughTheApi(MPI_COMM_WORLD);
  const io::ConfFile scans = io::readConf(conf);
  ASSERT_EQ(meta.scanHashes.size(), scans.scans.size());
  for (size_t i = 0; i < scans.scans.size(); ++i) {
    EXPECT_EQ(meta.scanNames[i], scans.scans[i].name);
    EXPECT_EQ(meta.scanHashes[i], io::fileHash(scans.scans[i].path)) << i;
  }
  // A missing file is read by one rank when the field is built; every rank gets its message.
  const std::string broken = sharedTempPath("api-broken.conf");
  if (mpi::rank() == 0)
    std::ofstream(broken) << "bmesh " << scans.scans[0].path << " 0 0 0 0 0 0 1\n"
                          << "bmesh nowhere.ply 0 0 0 0 0 0 1\n";
  MPI_Barrier(MPI_COMM_WORLD);
  Fusion missing(field, MPI_COMM_WORLD);
  missing.addScans(broken);
  const std::string message = messageOf([&] { missing.mesh(); });
  EXPECT_NE(message.find("nowhere.ply"), std::string::npos) << message;
  const std::string absent = sharedTempPath("absent.conf");
  EXPECT_NE(messageOf([&] { missing.addScans(absent); }).find(absent), std::string::npos);
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() != 0) return;
  std::filesystem::remove(checkpoint);
  std::filesystem::remove(broken);
  ASSERT_GT(listed.faces.size(), 10000u);
  EXPECT_EQ(listed.faces, added.faces);
  EXPECT_EQ(listed.vertices, added.vertices);
}
