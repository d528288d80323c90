// The one description of fuse's options: names and keys unique, every value round-trips
// through the command line's text and through JSON (reports, checkpoints), and each check
// names its option.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "rangefuse/core/Error.h"
#include "rangefuse/options/FuseParameters.h"

namespace rangefuse {
namespace {

/// Options with every value changed from its default.
FuseOptions changed() {
  FuseOptions o;
  o.scans = "a.conf", o.outputs.out = "m.ply", o.registration.anchor = "scan_003",
  o.outputs.report = "r.json";
  o.outputs.preview = "p.png", o.outputs.posesOut = "p.conf", o.outputs.checkpoint = "c.h5",
  o.outputs.resume = "old.h5";
  o.field.method = FieldMethod::Robust, o.registration.mode = RegistrationMode::Both;
  o.registration.field = RegistrationFieldMode::Rebuild,
  o.registration.solve = RegistrationSolve::PerScan;
  o.field.voxel = 0.00125, o.field.envelope = 2.5, o.field.brick = 16, o.minWeight = 0.25f,
  o.normals = false;
  o.surface.normalPasses = 3, o.surface.depthNormalPasses = 1, o.surface.maxEdgeFactor = 5;
  o.surface.minCosine = 0.3;
  o.mergeCells = 1.5, o.smoothNoise = 0.5, o.joinFlat = 0.1, o.field.quorum = 0.7,
  o.field.minViews = 3, o.field.edgeAngle = 60, o.field.sameDistance = 1.5;
  o.field.sameAngle = 30, o.field.freeMargin = INFINITY, o.field.fillHoles = true,
  o.registration.controlStride = 4;
  o.registration.maxIterations = 7;
  o.registration.maxRounds = 2, o.registration.roundTolerance = 0.05,
  o.outputs.checkpointEvery = 30, o.scanMemory = 0;
  o.field.threads = 3, o.source.format = "tum", o.source.intrinsics = "525,525,319.5,239.5";
  o.source.depthMax = 3, o.bandCells = 1e6, o.source.depthScale = 4000, o.stream.track = "on";
  o.stream.firstPose = "1,2,3,0,0,0,1", o.stream.minInliers = 0.4, o.stream.maxStep = 12,
  o.stream.skipLost = false, o.stream.closeLoops = true;
  o.outputs.trajectoryOut = "t.txt", o.stream.previewEvery = 5, o.stream.follow = true,
  o.stream.followTimeout = 30;
  o.field.colour = "none", o.outputs.previewView = "30,-10", o.quiet = true, o.verbose = true;
  o.outputs.overwrite = true, o.outputs.up = "z";
  return o;
}

TEST(FuseParameters, NamesAndKeysAreUnique) {
  std::set<std::string> options, keys;
  for (const FuseParameter& p : fuseParameters()) {
    EXPECT_TRUE(options.insert(p.option).second) << p.option;
    EXPECT_EQ(p.key.empty(), p.recorded == Recorded::No) << p.option;
    if (!p.key.empty()) {
      EXPECT_TRUE(keys.insert(p.key).second) << p.key;
    }
    EXPECT_FALSE(p.help.empty()) << p.option;
  }
}

TEST(FuseParameters, EveryValueRoundTripsThroughTextAndJson) {
  const FuseOptions from = changed();
  for (const FuseParameter& p : fuseParameters()) {
    FuseOptions byText, byJson;
    parseParameter(p, byText, parameterText(p, from));
    setParameter(p, byJson, nlohmann::json::parse(parameterJson(p, from).dump()));
    EXPECT_EQ(parameterJson(p, byText), parameterJson(p, from)) << p.option;
    EXPECT_EQ(parameterText(p, byJson), parameterText(p, from)) << p.option;
    EXPECT_NE(parameterText(p, from), parameterText(p, FuseOptions{})) << p.option << " unchanged";
  }
}

TEST(FuseParameters, TheReportHoldsExactlyTheResultParameters) {
  const nlohmann::json report = resultParameters(changed());
  size_t result = 0;
  for (const FuseParameter& p : fuseParameters())
    if (p.recorded == Recorded::Result) {
      ++result;
      EXPECT_TRUE(report.contains(p.key)) << p.key;
    }
  EXPECT_EQ(report.size(), result);
  EXPECT_EQ(report["method"], "robust");
  EXPECT_EQ(report["register"], "both");
}

TEST(FuseParameters, ABadValueIsRefusedNamingItsOption) {
  const FuseParameter* brick = nullptr;
  for (const FuseParameter& p : fuseParameters())
    if (p.option == "brick") brick = &p;
  ASSERT_NE(brick, nullptr);
  FuseOptions o = changed();
  EXPECT_THROW(parseParameter(*brick, o, "8.5"), InputError);
  EXPECT_THROW(parseParameter(*brick, o, ""), InputError);
  parseParameter(*brick, o, "1");
  try {
    validateFuseOptions(o);
    FAIL() << "brick 1 passed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--brick"), std::string::npos) << e.what();
  }
  o.field.brick = 8;
  EXPECT_THROW(validateFuseOptions(o), InputError);  // --quiet with --verbose
  o.verbose = false;
  EXPECT_NO_THROW(validateFuseOptions(o));
}

TEST(FuseParameters, GroupsSayWhichCommandsTakeAnOption) {
  std::map<std::string, OptionGroup> groupOf;
  for (const FuseParameter& p : fuseParameters()) groupOf[p.option] = p.group;
  // Commands that only build a field (render) take what the field needs, nothing a run writes,
  // registers or tracks.
  for (const char* option : {"scans", "scan-format", "voxel", "method", "merge-cells", "threads"})
    EXPECT_TRUE(buildsField(groupOf.at(option))) << option;
  for (const char* option :
       {"out", "report", "preview", "normals", "register", "register-solve", "poses-out", "track",
        "follow", "follow-timeout", "preview-every", "trajectory-out", "checkpoint", "resume"})
    EXPECT_FALSE(buildsField(groupOf.at(option))) << option;
  // Every group has options and a heading of its own.
  std::set<std::string> titles;
  for (OptionGroup g :
       {OptionGroup::Input, OptionGroup::Field, OptionGroup::Output, OptionGroup::Registration,
        OptionGroup::Tracking, OptionGroup::Checkpoint, OptionGroup::Resources}) {
    EXPECT_TRUE(titles.insert(groupTitle(g)).second) << groupTitle(g);
    bool any = false;
    for (const auto& [option, group] : groupOf) any |= group == g;
    EXPECT_TRUE(any) << groupTitle(g);
  }
}

TEST(MethodRegistry, EveryMethodIsNamedAndParsedBack) {
  for (const MethodInfo& m : methodRegistry()) {
    EXPECT_EQ(parseFieldMethod("method", m.name), m.id);
    EXPECT_EQ(&methodInfo(m.id), &m);
  }
  EXPECT_THROW(parseFieldMethod("method", "Prism"), InputError);
  EXPECT_EQ(parseRegistrationMode("register", toString(RegistrationMode::Simultaneous)),
            RegistrationMode::Simultaneous);
}

}  // namespace
}  // namespace rangefuse
