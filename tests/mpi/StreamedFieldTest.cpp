// The streamed prism field (each rank reads a share, triangles routed to brick owners) equals
// the field built from scans replicated on every rank, voxel by voxel and bit for bit, whatever
// the rank count, the thread count, the scan memory budget or the collective chunk size.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "ReplicatedField.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/route/ScanLoader.h"

using namespace rangefuse;

namespace {

FuseOptions bunnyOptions() {
  FuseOptions o;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.field.voxel = 0.002;
  return o;
}

/// The simple method: every rank reads every scan, made compact once placed as a streamed
/// field's are (decision 45), and adds all of them.
void replicatedField(const FuseOptions& o, FusedField& field) {
  const RunSettings s = runSettings(o);
  std::vector<PrismScan> world;
  for (const auto& c : io::readConf(o.scans).scans)
    world.push_back(
        compactScan(placeScan(loadScan(c, s.read.surface, s.read.limits, s.read.eps), c.pose)));
  test::replicatedFieldOf(s.field, std::move(world), MPI_COMM_WORLD, field);
}

void streamedField(const FuseOptions& o, FusedField& field, RankCounters& counters) {
  const RunSettings s = runSettings(o);
  Progress progress(MPI_COMM_WORLD);
  ASSERT_TRUE(buildField(s.read, s.field, MPI_COMM_WORLD, progress, field, counters));
  EXPECT_TRUE(field.scans.empty()) << "a streamed field keeps no scans";
}

/// Same bricks, same owners, same bits in every voxel of this rank.
void expectSameField(const FusedField& a, const FusedField& b) {
  ASSERT_EQ(a.layout.codes, b.layout.codes);
  ASSERT_EQ(a.layout.rankStart, b.layout.rankStart);
  ASSERT_EQ(a.layout.firstCodes, b.layout.firstCodes);
  ASSERT_EQ(a.layout.globalStart, b.layout.globalStart);
  ASSERT_EQ(a.layout.work, b.layout.work);
  EXPECT_EQ(a.layout.grid.origin, b.layout.grid.origin);
  const auto &sa = a.store->sums(), &sb = b.store->sums();
  ASSERT_EQ(sa.size(), sb.size());
  size_t differing = 0;
  for (size_t i = 0; i < sa.size(); ++i)
    differing += std::memcmp(&sa[i], &sb[i], sizeof(VoxelSums)) != 0;
  EXPECT_EQ(differing, 0u) << "of " << sa.size() << " voxels on rank " << mpi::rank();
}

TEST(StreamedField, EqualsTheReplicatedFieldVoxelByVoxel) {
  FusedField simple, streamed;
  RankCounters counters;
  replicatedField(bunnyOptions(), simple);
  streamedField(bunnyOptions(), streamed, counters);
  expectSameField(simple, streamed);
  EXPECT_EQ(streamed.scanCount, 10u);
  EXPECT_EQ(streamed.scanTriangles, simple.scanTriangles);
  EXPECT_GT(simple.scanTriangles, 0u);
}

TEST(StreamedField, ReReadingScansPastTheBudgetChangesNothing) {
  FuseOptions kept = bunnyOptions(), reread = bunnyOptions();
  reread.scanMemory = 0;  // every scan is read three times (bounds, plan, field)
  FusedField a, b;
  RankCounters ca, cb;
  streamedField(kept, a, ca);
  streamedField(reread, b, cb);
  expectSameField(a, b);
}

TEST(StreamedField, ThreadsChangeNothing) {
  // Each thread reads its own scans and adds prisms to its own slab of voxels: any thread count
  // gives the single-threaded field, and counts every prism and voxel update once.
  // 3 mm voxels keep the three builds quick (under ASan too).
  FuseOptions base = bunnyOptions();
  base.field.voxel = 0.003;
  FusedField simple;
  RankCounters one;
  streamedField(base, simple, one);
  for (int threads : {3, 7}) {
    FuseOptions o = base;
    o.field.threads = threads;
    FusedField field;
    RankCounters counters;
    streamedField(o, field, counters);
    expectSameField(simple, field);
    EXPECT_EQ(counters.prisms, one.prisms) << threads << " threads";
    EXPECT_EQ(counters.voxelUpdates, one.voxelUpdates) << threads << " threads";
  }
  EXPECT_GT(one.voxelUpdates, 0u);
}

TEST(StreamedField, TinyCollectiveChunksChangeNothing) {
  FusedField a, b;
  RankCounters ca, cb;
  streamedField(bunnyOptions(), a, ca);
  setenv("RANGEFUSE_MPI_CHUNK_BYTES", "65536", 1);
  streamedField(bunnyOptions(), b, cb);
  unsetenv("RANGEFUSE_MPI_CHUNK_BYTES");
  expectSameField(a, b);
}

TEST(StreamedField, RanksAddOnlyPrismsThatTouchTheirBricks) {
  FusedField field;
  RankCounters counters;
  streamedField(bunnyOptions(), field, counters);
  // Every routed triangle was rasterised (touches an owned brick), and together the ranks
  // received every triangle at least once.
  uint64_t prisms = counters.prisms;
  MPI_Allreduce(MPI_IN_PLACE, &prisms, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(prisms, field.routedCopies);
  EXPECT_LE(prisms, field.scanTriangles * 2);
  if (mpi::size() == 1) {
    EXPECT_EQ(field.routedBytes, 0u);
  }
}

}  // namespace
