#include "rangefuse/parallel/WorkStealing.h"

#include <sched.h>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <exception>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::mpi {
namespace {

constexpr int kAsk = 1;   // an empty message: "give me some of your items"
constexpr int kGive = 2;  // the answer: the items given (uint64), none when there are none

/// One rank's side of forEachStealing, on a communicator of its own (no other traffic can
/// match its tags).
class Stealer {
 public:
  Stealer(std::vector<size_t> mine, MPI_Comm comm)
      : todo_(mine.begin(), mine.end()), comm_(comm), me_(rank(comm)), ranks_(size(comm)) {}

  /// Works the own list, then the items taken from others until none is left anywhere.
  void run(size_t batch, const std::function<void(const std::vector<size_t>&)>& work) {
    do {
      while (!todo_.empty()) {
        answer();
        workBatch(batch, work);
      }
    } while (!failure_ && steal());
    finish();
    if (failure_) std::rethrow_exception(failure_);
  }

  std::vector<size_t>& worked() { return worked_; }

 private:
  void workBatch(size_t batch, const std::function<void(const std::vector<size_t>&)>& work) {
    std::vector<size_t> items;
    while (!todo_.empty() && items.size() < batch) {
      items.push_back(todo_.front());
      todo_.pop_front();
    }
    try {
      work(items);
      worked_.insert(worked_.end(), items.begin(), items.end());
    } catch (...) {
      failure_ = std::current_exception();
      todo_.clear();  // what is left is never worked: the run fails anyway
    }
  }

  /// Answers every request waiting: the back half of what is left (rounded down) each.
  void answer() {
    int waiting = 0;
    MPI_Status st;
    while (MPI_Iprobe(MPI_ANY_SOURCE, kAsk, comm_, &waiting, &st), waiting) {
      MPI_Recv(nullptr, 0, MPI_BYTE, st.MPI_SOURCE, kAsk, comm_, MPI_STATUS_IGNORE);
      std::vector<uint64_t> given(todo_.size() / 2);
      const auto from = todo_.end() - static_cast<std::ptrdiff_t>(given.size());
      std::copy(from, todo_.end(), given.begin());
      todo_.erase(from, todo_.end());
      MPI_Send(given.data(), static_cast<int>(given.size()), MPI_UINT64_T, st.MPI_SOURCE, kGive,
               comm_);
    }
  }

  /// Asks the other ranks in turn for items; true when one gave some (now in todo_).
  bool steal() {
    for (int k = 1; k < ranks_; ++k) {
      const int victim = (me_ + k) % ranks_;
      MPI_Send(nullptr, 0, MPI_BYTE, victim, kAsk, comm_);
      int ready = 0;
      MPI_Status st;
      // Answer others while waiting: they may be waiting on this rank at the same time.
      while (MPI_Iprobe(victim, kGive, comm_, &ready, &st), !ready) {
        answer();
        sched_yield();
      }
      int count = 0;
      MPI_Get_count(&st, MPI_UINT64_T, &count);
      std::vector<uint64_t> given(static_cast<size_t>(count));
      MPI_Recv(given.data(), count, MPI_UINT64_T, victim, kGive, comm_, MPI_STATUS_IGNORE);
      if (!given.empty()) {
        todo_.assign(given.begin(), given.end());
        return true;
      }
    }
    return false;
  }

  /// Waits until every rank has finished, answering (with nothing) whoever still asks.
  void finish() {
    MPI_Request all;
    MPI_Ibarrier(comm_, &all);
    int done = 0;
    while (MPI_Test(&all, &done, MPI_STATUS_IGNORE), !done) {
      answer();
      sched_yield();
    }
  }

  std::deque<size_t> todo_;
  std::vector<size_t> worked_;
  std::exception_ptr failure_;
  MPI_Comm comm_;
  int me_, ranks_;
};

}  // namespace

std::vector<size_t> forEachStealing(std::vector<size_t> mine, size_t batch,
                                    const std::function<void(const std::vector<size_t>&)>& work,
                                    MPI_Comm comm) {
  MPI_Comm own;
  MPI_Comm_dup(comm, &own);
  Stealer stealer(std::move(mine), own);
  try {
    stealer.run(std::max<size_t>(1, batch), work);
  } catch (...) {
    MPI_Comm_free(&own);
    throw;
  }
  MPI_Comm_free(&own);
  return std::move(stealer.worked());
}

}  // namespace rangefuse::mpi
