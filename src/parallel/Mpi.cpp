#include "rangefuse/parallel/Mpi.h"

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <limits>

namespace rangefuse::mpi {
namespace {

constexpr int kChunkTag = 7101;
constexpr int kPassTag = 7102;

/// Sends `sendCount` bytes to `to` while receiving `recvCount` bytes from `from`, in messages
/// of at most chunkBytes() each, so that no MPI count ever passes INT_MAX. The two directions
/// are posted separately: both ends of each directed pair agree on its number of messages, and
/// a bounded window of them is in flight at once.
void sendrecvChunked(const char* send, uint64_t sendCount, int to, char* recv, uint64_t recvCount,
                     int from, MPI_Comm comm) {
  constexpr uint64_t kWindow = 64;
  const uint64_t chunk = chunkBytes();
  const uint64_t sends = (sendCount + chunk - 1) / chunk, recvs = (recvCount + chunk - 1) / chunk;
  std::vector<MPI_Request> requests;
  for (uint64_t first = 0; first < std::max(sends, recvs); first += kWindow) {
    requests.clear();
    for (uint64_t i = first; i < std::min(recvs, first + kWindow); ++i)
      MPI_Irecv(recv + i * chunk, static_cast<int>(std::min(chunk, recvCount - i * chunk)),
                MPI_CHAR, from, kChunkTag, comm, &requests.emplace_back());
    for (uint64_t i = first; i < std::min(sends, first + kWindow); ++i)
      MPI_Isend(send + i * chunk, static_cast<int>(std::min(chunk, sendCount - i * chunk)),
                MPI_CHAR, to, kChunkTag, comm, &requests.emplace_back());
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  }
}

/// Every rank's count for this rank (sizes[r] = what rank r will send here).
std::vector<uint64_t> exchangeSizes(const std::vector<uint64_t>& out, MPI_Comm comm) {
  std::vector<uint64_t> in(out.size());
  MPI_Alltoall(out.data(), 1, MPI_UINT64_T, in.data(), 1, MPI_UINT64_T, comm);
  return in;
}

}  // namespace

int rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

int size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

uint64_t chunkBytes() {
  // Read on every call so that a test can change it between collectives (cheap next to one).
  const uint64_t fallback = uint64_t{1} << 30;
  const char* env = std::getenv("RANGEFUSE_MPI_CHUNK_BYTES");
  if (!env) return fallback;
  const unsigned long long v = std::strtoull(env, nullptr, 10);
  return v >= 1 && v <= static_cast<unsigned long long>(std::numeric_limits<int>::max())
             ? static_cast<uint64_t>(v)
             : fallback;
}

namespace {
thread_local CapturedFailure* capture = nullptr;
}  // namespace

CapturedFailure::CapturedFailure() : outer_(capture) {
  capture = this;
}
CapturedFailure::~CapturedFailure() {
  capture = outer_;
}
CapturedFailure* CapturedFailure::current() {
  return capture;
}

void CapturedFailure::keep(const std::string& message) {
  if (message_.empty()) message_ = message;
}

bool agree(bool ok, const std::string& message, MPI_Comm comm) {
  int mine = ok ? size(comm) : rank(comm), first = 0;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size(comm)) return true;
  if (capture) {
    std::string text = first == rank(comm) ? message : std::string();
    uint64_t length = text.size();
    MPI_Bcast(&length, 1, MPI_UINT64_T, first, comm);
    text.resize(length);
    MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, first, comm);
    if (!text.empty()) capture->keep(text);
    return false;
  }
  if (first == rank(comm) && !message.empty())
    std::cerr << "rangefuse: error: " << message << std::endl;
  return false;
}

std::vector<std::vector<char>> exchangeBytes(std::vector<std::vector<char>> out, MPI_Comm comm) {
  std::vector<std::vector<char>> in(size(comm));
  exchangeBytes(std::move(out), comm,
                [&](int from, std::vector<char>&& bytes) { in[from] = std::move(bytes); });
  return in;
}

void exchangeBytes(std::vector<std::vector<char>> out, MPI_Comm comm,
                   const std::function<void(int, std::vector<char>&&)>& received) {
  const int n = size(comm), me = rank(comm);
  std::vector<uint64_t> sizes(n);
  for (int r = 0; r < n; ++r) sizes[r] = out[r].size();
  const std::vector<uint64_t> incoming = exchangeSizes(sizes, comm);
  received(me, std::move(out[me]));  // this rank's own part, uncopied
  // Round k pairs every rank with the ranks k ahead and k behind: no rank waits on another.
  for (int k = 1; k < n; ++k) {
    const int to = (me + k) % n, from = (me - k + n) % n;
    std::vector<char> in(incoming[from]);
    sendrecvChunked(out[to].data(), out[to].size(), to, in.data(), incoming[from], from, comm);
    std::vector<char>().swap(out[to]);  // sent: what arrives may take its place
    received(from, std::move(in));
  }
}

Eigen::AlignedBox3d unitedBox(const Eigen::AlignedBox3d& mine, MPI_Comm comm) {
  // One reduction: the corners' minimum and the negated maximum (negation is exact).
  double v[6] = {mine.min().x(),  mine.min().y(),  mine.min().z(),
                 -mine.max().x(), -mine.max().y(), -mine.max().z()};
  MPI_Allreduce(MPI_IN_PLACE, v, 6, MPI_DOUBLE, MPI_MIN, comm);
  return Eigen::AlignedBox3d(Eigen::Vector3d(v[0], v[1], v[2]),
                             Eigen::Vector3d(-v[3], -v[4], -v[5]));
}

std::map<size_t, std::string> gatherIndexed(const std::map<size_t, std::string>& mine, int root,
                                            MPI_Comm comm) {
  std::vector<char> bytes;
  for (const auto& [i, text] : mine) {
    const uint64_t head[2] = {i, text.size()};
    pack(bytes, head, 2);
    pack(bytes, text.data(), text.size());
  }
  std::vector<std::vector<char>> parts;
  if (root < 0)
    parts = allgatherBytes(bytes, comm);
  else
    parts.push_back(gatherBytes(bytes, root, comm));
  std::map<size_t, std::string> all;
  for (const std::vector<char>& part : parts)
    for (size_t pos = 0; pos < part.size();) {
      uint64_t head[2];
      unpack(part, pos, head, 2);
      all[head[0]].assign(part.data() + pos, head[1]);
      pos += head[1];
    }
  return all;
}

void passAlong(void* value, size_t bytes, const std::function<void()>& fold, MPI_Comm comm) {
  const int me = rank(comm), n = size(comm);
  const int count = static_cast<int>(bytes);
  if (me > 0) MPI_Recv(value, count, MPI_BYTE, me - 1, kPassTag, comm, MPI_STATUS_IGNORE);
  fold();
  if (me + 1 < n) MPI_Send(value, count, MPI_BYTE, me + 1, kPassTag, comm);
  MPI_Bcast(value, count, MPI_BYTE, n - 1, comm);
}

std::vector<std::vector<char>> allgatherBytes(const std::vector<char>& mine, MPI_Comm comm) {
  const int n = size(comm), me = rank(comm);
  uint64_t count = mine.size();
  std::vector<uint64_t> counts(n);
  MPI_Allgather(&count, 1, MPI_UINT64_T, counts.data(), 1, MPI_UINT64_T, comm);
  std::vector<std::vector<char>> in(n);
  in[me] = mine;
  for (int k = 1; k < n; ++k) {
    const int to = (me + k) % n, from = (me - k + n) % n;
    in[from].resize(counts[from]);
    sendrecvChunked(mine.data(), mine.size(), to, in[from].data(), counts[from], from, comm);
  }
  return in;
}

std::vector<char> gatherBytes(const std::vector<char>& mine, int root, MPI_Comm comm) {
  const int n = size(comm), me = rank(comm);
  uint64_t count = mine.size();
  std::vector<uint64_t> counts(n);
  MPI_Gather(&count, 1, MPI_UINT64_T, counts.data(), 1, MPI_UINT64_T, root, comm);
  if (me != root) {
    sendrecvChunked(mine.data(), count, root, nullptr, 0, MPI_PROC_NULL, comm);
    return {};
  }
  std::vector<char> all;
  uint64_t total = 0;
  for (uint64_t c : counts) total += c;
  all.reserve(total);
  for (int r = 0; r < n; ++r) {
    if (r == me) {
      all.insert(all.end(), mine.begin(), mine.end());
      continue;
    }
    const size_t at = all.size();
    all.resize(at + counts[r]);
    sendrecvChunked(nullptr, 0, MPI_PROC_NULL, all.data() + at, counts[r], r, comm);
  }
  return all;
}

std::string broadcastString(const std::string& s, int root, MPI_Comm comm) {
  uint64_t n = s.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, root, comm);
  std::string out = s;
  out.resize(n);
  for (uint64_t done = 0; done < n; done += chunkBytes())
    MPI_Bcast(out.data() + done, static_cast<int>(std::min(chunkBytes(), n - done)), MPI_CHAR, root,
              comm);
  return out;
}

}  // namespace rangefuse::mpi
