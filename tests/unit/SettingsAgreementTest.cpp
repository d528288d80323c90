// The command and the library refuse the same values of each setting they share with the same
// message: every setting of FieldSettings and ScanSourceOptions (the ones Fusion takes) is
// given values of its type around the checks' bounds, through the command's option table and
// through Fusion.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/rangefuse.h"

namespace rangefuse {
namespace {

/// Values of the setting's type, as the command line writes them.
std::vector<std::string> candidates(const SettingValue& v) {
  return std::visit(
      Overloaded{[](double*) -> std::vector<std::string> {
                   return {"-1", "0",  "0.5", "1",    "2",   "64",
                           "65", "91", "181", "1001", "inf", "nan"};
                 },
                 [](float*) -> std::vector<std::string> {
                   return {"-1", "0", "inf", "nan"};
                 },
                 [](int*) -> std::vector<std::string> { return {"-1", "0", "1", "2", "64", "65"}; },
                 [](bool*) -> std::vector<std::string> {
                   return {"true", "false"};
                 },
                 [](std::string*) -> std::vector<std::string> {
                   return {"", "auto", "rgb", "intensity", "none", "on", "tum", "bogus"};
                 },
                 [](const EnumValue&) -> std::vector<std::string> {
                   return {"prism", "robust", "consensus", "naive"};
                 }},
      v);
}

/// A run that is valid but for the option tried.
FuseOptions valid() {
  FuseOptions o;
  o.scans = "none.conf";
  o.field.voxel = 0.01;
  o.outputs.out = "none.ply";
  return o;
}

std::string commandRefusal(const FuseOptions& o) {
  try {
    validateFuseOptions(o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

template <class Call>
std::string libraryRefusal(Call&& call, const std::string& option) {
  try {
    call();
  } catch (const InputError& e) {
    const std::string message = e.what();
    return message.rfind("--" + option, 0) == 0 ? message : "";  // else: the missing list
  }
  return "";
}

const FuseParameter& parameter(const std::string& option) {
  for (const FuseParameter& p : fuseParameters())
    if (p.option == option) return p;
  throw std::logic_error("no option --" + option);
}

/// For every setting of `table`, at values of its type: `library(options, option)` refuses
/// exactly what the command refuses, with its message. Returns how many values were refused.
template <class S, class Library>
int expectAgreement(const std::vector<Setting<S>>& table, Library library) {
  int refused = 0;
  for (const Setting<S>& s : table) {
    const FuseParameter& p = parameter(s.option);  // every such setting is an option
    FuseOptions probe = valid();
    for (const std::string& text : candidates(p.value(probe))) {
      FuseOptions o = valid();
      parseParameter(p, o, text);
      const std::string command = commandRefusal(o);
      EXPECT_EQ(library(o, s.option), command) << "--" << s.option << " " << text;
      refused += !command.empty();
    }
  }
  return refused;
}

TEST(SettingsAgreement, FusionRefusesWhatTheCommandRefusesWithItsMessage) {
  const int refused = expectAgreement(
      FieldSettings::settings(), [](const FuseOptions& o, const std::string& option) {
        return libraryRefusal([&] { Fusion f(o.field, MPI_COMM_NULL); }, option);
      });
  EXPECT_GT(refused, 20);  // the values do reach the checks
}

TEST(SettingsAgreement, AddScansRefusesWhatTheCommandRefusesWithItsMessage) {
  FieldSettings field;
  field.voxel = 0.01;
  Fusion fusion(field, MPI_COMM_NULL);
  const int refused = expectAgreement(
      io::ScanSourceOptions::settings(), [&](const FuseOptions& o, const std::string& option) {
        return libraryRefusal([&] { fusion.addScans("none.conf", o.source); }, option);
      });
  EXPECT_GT(refused, 5);
}

TEST(SettingsAgreement, EachOptionIsDefinedOnce) {
  std::set<std::string> options, keys;
  for (const FuseParameter& p : fuseParameters()) {
    EXPECT_TRUE(options.insert(p.option).second) << "--" << p.option << " twice";
    if (!p.key.empty()) {
      EXPECT_TRUE(keys.insert(p.key).second) << p.key << " twice";
    }
  }
}

}  // namespace
}  // namespace rangefuse
