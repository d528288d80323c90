// parallel/Mpi.h and MpiTraffic.h: the byte collectives give the same bytes whatever the chunk
// size, including chunk sizes that do not divide the messages and messages of zero bytes
// (RANGEFUSE_MPI_CHUNK_BYTES); boxes and indexed texts joined across ranks; traffic counted;
// MpiStart.h: the messaging layer a job on one machine starts with.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <string>

#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/MpiStart.h"
#include "rangefuse/parallel/MpiTraffic.h"

namespace rangefuse {
namespace {

/// The bytes rank `from` sends to rank `to`: a length and content both ranks can compute.
std::vector<char> message(int from, int to) {
  const size_t n = (from * 131 + to * 17) % 97 + (from == to ? 0 : 3 * (from + to));
  std::vector<char> m(n);
  for (size_t i = 0; i < n; ++i) m[i] = static_cast<char>((i * 31 + from * 7 + to * 13) & 0xff);
  return m;
}

class ChunkedCollectives : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override { setenv("RANGEFUSE_MPI_CHUNK_BYTES", GetParam(), 1); }
  void TearDown() override { unsetenv("RANGEFUSE_MPI_CHUNK_BYTES"); }
  const int me = mpi::rank(), n = mpi::size();
};

TEST_P(ChunkedCollectives, ExchangeDeliversEveryPairsBytes) {
  std::vector<std::vector<char>> out(n);
  for (int r = 0; r < n; ++r) out[r] = message(me, r);
  const auto in = mpi::exchangeBytes(out, MPI_COMM_WORLD);
  ASSERT_EQ(in.size(), static_cast<size_t>(n));
  for (int r = 0; r < n; ++r) EXPECT_EQ(in[r], message(r, me)) << "from rank " << r;
}

TEST_P(ChunkedCollectives, AllgatherGivesEveryRankAll) {
  const auto all = mpi::allgatherBytes(message(me, 0), MPI_COMM_WORLD);
  for (int r = 0; r < n; ++r) EXPECT_EQ(all[r], message(r, 0)) << "from rank " << r;
}

TEST_P(ChunkedCollectives, GatherConcatenatesInRankOrderOnTheRoot) {
  const int root = n - 1;
  const std::vector<char> all = mpi::gatherBytes(message(me, root), root, MPI_COMM_WORLD);
  std::vector<char> expected;
  for (int r = 0; r < n && me == root; ++r) {
    const auto m = message(r, root);
    expected.insert(expected.end(), m.begin(), m.end());
  }
  EXPECT_EQ(all, expected);
}

TEST_P(ChunkedCollectives, BroadcastStringArrivesWhole) {
  const std::string s(1000 + 7, 'x');
  std::string mine = me == 0 ? s : "";
  EXPECT_EQ(mpi::broadcastString(mine, 0, MPI_COMM_WORLD), s);
}

INSTANTIATE_TEST_SUITE_P(ChunkSizes, ChunkedCollectives,
                         ::testing::Values("1", "3", "64", "1073741824"));

TEST(ChunkedCollectives, ChunkSizeComesFromTheEnvironment) {
  setenv("RANGEFUSE_MPI_CHUNK_BYTES", "5", 1);
  EXPECT_EQ(mpi::chunkBytes(), 5u);
  setenv("RANGEFUSE_MPI_CHUNK_BYTES", "0", 1);  // nonsense falls back to the default
  EXPECT_EQ(mpi::chunkBytes(), uint64_t{1} << 30);
  unsetenv("RANGEFUSE_MPI_CHUNK_BYTES");
  EXPECT_EQ(mpi::chunkBytes(), uint64_t{1} << 30);
}

TEST(Mpi, UnitedBoxHoldsEveryRanksBoxAndNoMore) {
  const int me = mpi::rank(), n = mpi::size();
  // Rank r: a box around (r, -2r, 0.5) of half-size 1, except rank 1's, which is empty.
  Eigen::AlignedBox3d mine;
  const Eigen::Vector3d centre(me, -2.0 * me, 0.5);
  if (me != 1)
    mine.extend(centre - Eigen::Vector3d::Ones()).extend(centre + Eigen::Vector3d::Ones());
  Eigen::AlignedBox3d expected;
  for (int r = 0; r < n; ++r) {
    if (r == 1) continue;
    const Eigen::Vector3d c(r, -2.0 * r, 0.5);
    expected.extend(c - Eigen::Vector3d::Ones()).extend(c + Eigen::Vector3d::Ones());
  }
  const Eigen::AlignedBox3d got = mpi::unitedBox(mine, MPI_COMM_WORLD);
  EXPECT_EQ(got.min(), expected.min());
  EXPECT_EQ(got.max(), expected.max());
  EXPECT_TRUE(mpi::unitedBox(Eigen::AlignedBox3d(), MPI_COMM_WORLD).isEmpty());
}

TEST(Mpi, GatherIndexedJoinsEveryRanksEntries) {
  const int me = mpi::rank(), n = mpi::size();
  // Rank r gives entries r, r + n, r + 2n; texts hold newlines, spaces, or nothing at all.
  const auto text = [](size_t i) {
    return i % 3 == 0 ? std::string() : "entry " + std::to_string(i) + "\nline two";
  };
  std::map<size_t, std::string> mine, expected;
  for (size_t i = me; i < static_cast<size_t>(3 * n); i += n) mine[i] = text(i);
  for (size_t i = 0; i < static_cast<size_t>(3 * n); ++i) expected[i] = text(i);
  EXPECT_EQ(mpi::gatherIndexed(mine, -1, MPI_COMM_WORLD), expected);
  const int root = n - 1;
  const auto onRoot = mpi::gatherIndexed(mine, root, MPI_COMM_WORLD);
  if (me == root)
    EXPECT_EQ(onRoot, expected);
  else
    EXPECT_TRUE(onRoot.empty());
}

TEST(MpiTraffic, CountsEveryByteAnExchangeMoves) {
  // Chunks of 7 bytes: a message of m bytes goes as ceil(m / 7) sends and receives.
  setenv("RANGEFUSE_MPI_CHUNK_BYTES", "7", 1);
  const int me = mpi::rank(), n = mpi::size();
  std::vector<std::vector<char>> out(n);
  uint64_t sent = 0, received = 0, messages = 0;
  for (int r = 0; r < n; ++r) {
    out[r] = message(me, r);
    if (r == me) continue;
    sent += message(me, r).size(), received += message(r, me).size();
    messages += (message(me, r).size() + 6) / 7 + (message(r, me).size() + 6) / 7;
  }
  const mpi::Traffic before = mpi::traffic();
  mpi::exchangeBytes(out, MPI_COMM_WORLD);
  const mpi::Traffic after = mpi::traffic();
  unsetenv("RANGEFUSE_MPI_CHUNK_BYTES");
  // The sizes go first: one all-to-all of a uint64 for every rank.
  const uint64_t sizes = sizeof(uint64_t) * n;
  EXPECT_EQ(after.bytesSent - before.bytesSent, sent + sizes);
  EXPECT_EQ(after.bytesReceived - before.bytesReceived, received + sizes);
  EXPECT_EQ(after.calls - before.calls, messages + 1);
}

TEST(MpiStart, AJobOnOneMachineUsesTheMessagingLayerItWasGiven) {
  // ctest starts this job with mpirun on this machine: start() chose ob1 unless the user did
  // (OMPI_MCA_pml set first), and Open MPI read that choice, as its own variable shows.
  if (!mpi::jobOnOneMachine()) GTEST_SKIP() << "started across machines or by another launcher";
  const char* chosen = std::getenv("OMPI_MCA_pml");
  ASSERT_NE(chosen, nullptr);
  int provided = 0, index = 0, count = 0;
  ASSERT_EQ(MPI_T_init_thread(MPI_THREAD_SINGLE, &provided), MPI_SUCCESS);
  ASSERT_EQ(MPI_T_cvar_get_index("pml", &index), MPI_SUCCESS);
  MPI_T_cvar_handle handle;
  ASSERT_EQ(MPI_T_cvar_handle_alloc(index, nullptr, &handle, &count), MPI_SUCCESS);
  std::string value(std::max(count, 1), '\0');
  EXPECT_EQ(MPI_T_cvar_read(handle, value.data()), MPI_SUCCESS);
  MPI_T_cvar_handle_free(&handle);
  MPI_T_finalize();
  EXPECT_STREQ(value.c_str(), chosen);
}

}  // namespace
}  // namespace rangefuse
