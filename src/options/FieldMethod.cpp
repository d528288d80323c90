#include "rangefuse/options/FieldMethod.h"

#include <array>
#include <utility>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

template <class E, size_t N>
const char* nameOf(const std::array<std::pair<E, const char*>, N>& names, E value) {
  for (const auto& [e, name] : names)
    if (e == value) return name;
  return "?";
}

template <class E, size_t N>
E parse(const std::array<std::pair<E, const char*>, N>& names, const std::string& option,
        const std::string& text) {
  std::string valid;
  for (const auto& [e, name] : names) {
    if (text == name) return e;
    valid += std::string(valid.empty() ? "" : ", ") + name;
  }
  throw InputError("--" + option + " must be one of " + valid + ", not '" + text + "'");
}

const std::array<std::pair<RegistrationMode, const char*>, 4> kRegistrationModes{
    {{RegistrationMode::None, "none"},
     {RegistrationMode::Incremental, "incremental"},
     {RegistrationMode::Simultaneous, "simultaneous"},
     {RegistrationMode::Both, "both"}}};

const std::array<std::pair<RegistrationFieldMode, const char*>, 2> kFieldModes{
    {{RegistrationFieldMode::Grow, "grow"}, {RegistrationFieldMode::Rebuild, "rebuild"}}};

const std::array<std::pair<RegistrationSolve, const char*>, 2> kSolves{
    {{RegistrationSolve::Joint, "joint"}, {RegistrationSolve::PerScan, "per-scan"}}};

std::array<std::pair<FieldMethod, const char*>, 4> methodNames() {
  std::array<std::pair<FieldMethod, const char*>, 4> names;
  for (size_t i = 0; i < names.size(); ++i)
    names[i] = {methodRegistry()[i].id, methodRegistry()[i].name};
  return names;
}

}  // namespace

const std::vector<MethodInfo>& methodRegistry() {
  static const std::vector<MethodInfo> methods{
      {FieldMethod::Prism, "prism", "prism fields (Tubic et al.): every observation, averaged",
       false, false},
      {FieldMethod::Robust, "robust",
       "prism samples kept by agreement or free space (docs/robust.md); registers against the "
       "prism field",
       false, true},
      {FieldMethod::Consensus, "consensus",
       "consensus surfaces (Wheeler et al.): a quorum of closest surfaces", true, false},
      {FieldMethod::Naive, "naive", "the closest surface of any view (baseline)", true, false}};
  return methods;
}

const MethodInfo& methodInfo(FieldMethod method) {
  for (const MethodInfo& m : methodRegistry())
    if (m.id == method) return m;
  return methodRegistry().front();
}

const char* toString(FieldMethod method) {
  return methodInfo(method).name;
}
const char* toString(RegistrationMode mode) {
  return nameOf(kRegistrationModes, mode);
}
const char* toString(RegistrationFieldMode mode) {
  return nameOf(kFieldModes, mode);
}
const char* toString(RegistrationSolve solve) {
  return nameOf(kSolves, solve);
}

FieldMethod parseFieldMethod(const std::string& option, const std::string& text) {
  return parse(methodNames(), option, text);
}

RegistrationMode parseRegistrationMode(const std::string& option, const std::string& text) {
  return parse(kRegistrationModes, option, text);
}

RegistrationFieldMode parseRegistrationFieldMode(const std::string& option,
                                                 const std::string& text) {
  return parse(kFieldModes, option, text);
}

RegistrationSolve parseRegistrationSolve(const std::string& option, const std::string& text) {
  return parse(kSolves, option, text);
}

}  // namespace rangefuse
