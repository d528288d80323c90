// parallel/MpiStart.h: which jobs count as running on one machine, from the launcher's variables.
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <string>

#include "rangefuse/parallel/MpiStart.h"

namespace rangefuse {
namespace {

/// Sets the launcher variables a case names and clears the others; puts them all back after.
class LauncherVariables : public ::testing::Test {
 protected:
  static constexpr const char* kNames[] = {
      "OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_LOCAL_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_FD",
      "SLURM_PROCID"};
  void SetUp() override {
    for (const char* name : kNames) {
      if (const char* v = std::getenv(name)) saved_[name] = v;
      unsetenv(name);
    }
  }
  void TearDown() override {
    for (const char* name : kNames) {
      unsetenv(name);
      if (saved_.count(name)) setenv(name, saved_[name].c_str(), 1);
    }
  }
  static void set(const char* name, const char* value) { setenv(name, value, 1); }

 private:
  std::map<std::string, std::string> saved_;
};

TEST_F(LauncherVariables, AProcessStartedAloneRunsOnOneMachine) {
  EXPECT_TRUE(mpi::jobOnOneMachine());
}

TEST_F(LauncherVariables, MpirunOntoOneNodeRunsOnOneMachine) {
  set("OMPI_COMM_WORLD_SIZE", "4"), set("OMPI_COMM_WORLD_LOCAL_SIZE", "4");
  set("PMIX_RANK", "2");  // mpirun sets PMIx's too
  EXPECT_TRUE(mpi::jobOnOneMachine());
}

TEST_F(LauncherVariables, MpirunOntoSeveralNodesDoesNot) {
  set("OMPI_COMM_WORLD_SIZE", "4"), set("OMPI_COMM_WORLD_LOCAL_SIZE", "2");
  EXPECT_FALSE(mpi::jobOnOneMachine());
  unsetenv("OMPI_COMM_WORLD_LOCAL_SIZE");  // not said: not known
  EXPECT_FALSE(mpi::jobOnOneMachine());
}

TEST_F(LauncherVariables, OtherLaunchersAreNotKnownToRunOnOneMachine) {
  for (const char* name : {"PMIX_RANK", "PMI_RANK", "PMI_FD", "SLURM_PROCID"}) {
    set(name, "0");
    EXPECT_FALSE(mpi::jobOnOneMachine()) << name;
    unsetenv(name);
  }
}

}  // namespace
}  // namespace rangefuse
