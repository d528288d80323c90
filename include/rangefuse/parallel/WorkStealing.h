// Work shared out by measured cost: each rank starts on its own list of items and, once done,
// takes the far end of another rank's remaining list, so that ranks finish together however
// unevenly the items cost.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace rangefuse::mpi {

/// Collective: calls work(batch) for every item of every rank's list exactly once, on one rank,
/// a batch of at most `batch` items at a time, in list order within a batch. A rank works
/// through its own list (`mine`) from the front; between batches it answers requests from
/// ranks whose lists are done by giving them the back half of what it has left (the items
/// nearest the next rank's along the list). Returns the items this rank worked, in the order
/// it worked them.
///
/// Which rank works an item depends on timing: callers must make results that do not depend
/// on it. An exception from work stops this rank's list (what it has left is never worked) but
/// not its answers to the others, so no rank waits on it; it is rethrown here once every rank
/// has finished, for the caller's agreement to report.
std::vector<size_t> forEachStealing(std::vector<size_t> mine, size_t batch,
                                    const std::function<void(const std::vector<size_t>&)>& work,
                                    MPI_Comm comm);

}  // namespace rangefuse::mpi
