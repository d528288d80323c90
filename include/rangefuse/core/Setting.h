// One setting a user can give, described where the settings struct that holds it is defined:
// its option name, the key reports and checkpoints keep it under, its help and the check of its
// value. Each stage's settings struct owns such a table and a validate() that walks it; the
// command's options, --help, reports, checkpoints, the library and the Python module all read
// the same tables, so an option's default (the struct's initialiser), check and description
// are written once.
#pragma once

#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "rangefuse/core/Error.h"

namespace rangefuse {

/// A setting held as an enumeration: read and written by name.
struct EnumValue {
  std::function<std::string()> name;
  /// Sets the value named `text`; throws InputError naming `option` when there is none.
  std::function<void(const std::string& option, const std::string& text)> set;
};

/// Where a setting's value lives in the struct that holds it.
using SettingValue = std::variant<double*, float*, int*, bool*, std::string*, EnumValue>;

/// Lambdas as one visitor of a SettingValue: std::visit(Overloaded{...}, value).
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

/// Whether a setting decides the result: kept in reports and checkpoints, and compared on
/// resume; kept in checkpoints only (the scan list, checked by hashes instead); or neither
/// (where outputs go, resources).
enum class Recorded { Result, CheckpointOnly, No };

/// Which part of a run a setting belongs to: commands that only build a field (render) take
/// the input, field and resource groups; --help lists the groups in this order.
enum class OptionGroup { Input, Field, Output, Registration, Tracking, Checkpoint, Resources };

/// One setting of the settings struct S.
template <class S>
struct Setting {
  std::string option;  ///< command-line name without "--"; Python's keyword has '_' for '-'
  std::string key;     ///< report and checkpoint key (empty when not recorded)
  Recorded recorded = Recorded::No;
  bool required = false;  ///< has no default: --help shows none
  OptionGroup group = OptionGroup::Field;
  std::string help;
  std::function<SettingValue(S&)> value;
  /// Empty when the value is acceptable, else what it must be ("must be ..."); may be null.
  std::function<std::string(const S&)> check;
  /// The value an option given without one takes (empty: it needs a value).
  const char* implicitValue = "";
};

/// The setting at `member` of S.
template <class S, class T>
std::function<SettingValue(S&)> at(T S::*member) {
  return [member](S& s) -> SettingValue { return &(s.*member); };
}

/// The enumeration at `member` of S, named by `name` and parsed by `parse(option, text)`.
template <class S, class E, class Name, class Parse>
std::function<SettingValue(S&)> enumAt(E S::*member, Name name, Parse parse) {
  return [=](S& s) -> SettingValue {
    E* v = &(s.*member);
    return EnumValue{[v, name] { return std::string(name(*v)); },
                     [v, parse](const std::string& option, const std::string& text) {
                       *v = parse(option, text);
                     }};
  };
}

/// A check from a condition on the setting's own value and the message when it fails.
template <class S, class T>
std::function<std::string(const S&)> must(T S::*member, bool (*ok)(T), const char* what) {
  return [member, ok, what](const S& s) -> std::string { return ok(s.*member) ? "" : what; };
}

/// The first failed check's message, as the command gives it ("--OPTION must be ..."), or "".
template <class S>
std::string firstProblem(const std::vector<Setting<S>>& table, const S& s) {
  for (const Setting<S>& setting : table) {
    const std::string wrong = setting.check ? setting.check(s) : "";
    if (!wrong.empty()) return "--" + setting.option + " " + wrong;
  }
  return "";
}

/// Throws InputError with the first failed check's message.
template <class S>
void validateSettings(const std::vector<Setting<S>>& table, const S& s) {
  const std::string wrong = firstProblem(table, s);
  if (!wrong.empty()) throw InputError(wrong);
}

/// The settings of `part` (a member of T holding an S) as settings of T: the same names,
/// help and checks, reached through the member.
template <class T, class S>
std::vector<Setting<T>> lift(const std::vector<Setting<S>>& table, S T::*part) {
  std::vector<Setting<T>> out;
  for (const Setting<S>& s : table) {
    Setting<T> t{s.option, s.key,   s.recorded, s.required,     s.group,
                 s.help,   nullptr, nullptr,    s.implicitValue};
    t.value = [part, value = s.value](T& whole) { return value(whole.*part); };
    if (s.check) t.check = [part, check = s.check](const T& whole) { return check(whole.*part); };
    out.push_back(std::move(t));
  }
  return out;
}

/// Sets the value from command-line text; throws InputError naming `--option`.
void parseSetting(const std::string& option, const SettingValue& value, const std::string& text);

/// The value as the command line writes it (the shortest text that reads back the same).
std::string settingText(const SettingValue& value);

/// Python's keyword for an option: '-' as '_'.
std::string keywordOf(const std::string& option);

}  // namespace rangefuse
