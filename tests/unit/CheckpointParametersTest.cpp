// Resuming takes the options a checkpoint recorded, and a checkpoint written before an option
// existed is resumed as its run was made.
#include <gtest/gtest.h>

#include "rangefuse/core/Error.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/pipeline/Checkpointing.h"

namespace rangefuse {
namespace {

io::CheckpointMeta metaOf(const FuseOptions& o) {
  io::CheckpointMeta meta;
  meta.parameters = resultParameters(o);
  return meta;
}

TEST(CheckpointParameters, OptionsNotGivenComeFromTheCheckpoint) {
  FuseOptions written;
  written.surface.depthNormalPasses = 3, written.joinFlat = 0.1;
  FuseOptions resumed;
  adoptCheckpointParameters(metaOf(written), resumed);
  EXPECT_EQ(resumed.surface.depthNormalPasses, 3);
  EXPECT_EQ(resumed.joinFlat, 0.1);
}

TEST(CheckpointParameters, ACheckpointFromBeforeAnOptionResumesAsItsRunWas) {
  io::CheckpointMeta meta = metaOf(FuseOptions{});
  meta.parameters.erase("depth_normal_passes");
  meta.parameters.erase("join_flat_voxels");
  FuseOptions resumed;
  adoptCheckpointParameters(meta, resumed);
  EXPECT_EQ(resumed.surface.depthNormalPasses, -1);  // depth frames as every scan
  EXPECT_EQ(resumed.joinFlat, 0);                    // no blocks joined
}

TEST(CheckpointParameters, AGivenOptionThatDiffersIsRefused) {
  FuseOptions resumed;
  resumed.surface.depthNormalPasses = 2;
  resumed.givenOptions.push_back("depth-normal-passes");
  try {
    adoptCheckpointParameters(metaOf(FuseOptions{}), resumed);
    FAIL() << "a differing option was taken";
  } catch (const InputError& e) {
    const std::string expected = "--depth-normal-passes 2 (checkpoint: " +
                                 std::to_string(FuseOptions{}.surface.depthNormalPasses) + ")";
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rangefuse
