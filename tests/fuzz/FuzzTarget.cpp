// libFuzzer driver: RANGEFUSE_FUZZ_ENTRY (set per target by CMake) names the entry.
#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzEntries.h"
#include "rangefuse/parallel/MpiStart.h"

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  setenv("OMPI_MCA_opal_signal", "", 1);  // crashes are libFuzzer's to catch and save
  rangefuse::mpi::start(argc, argv);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const rangefuse::fuzz::Entry entry = rangefuse::fuzz::entryNamed(RANGEFUSE_FUZZ_ENTRY);
  if (!entry) std::abort();
  entry(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
