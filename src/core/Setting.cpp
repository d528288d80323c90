#include "rangefuse/core/Setting.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace rangefuse {
namespace {

double number(const std::string& option, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE)
    throw InputError("--" + option + ": '" + text + "' is not a number");
  return v;
}

int integer(const std::string& option, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < INT32_MIN || v > INT32_MAX)
    throw InputError("--" + option + ": '" + text + "' is not a whole number");
  return static_cast<int>(v);
}

bool truth(const std::string& option, const std::string& text) {
  for (const char* yes : {"true", "1", "yes", "on"})
    if (text == yes) return true;
  for (const char* no : {"false", "0", "no", "off"})
    if (text == no) return false;
  throw InputError("--" + option + ": '" + text + "' is not true or false");
}

std::string shortest(double v) {
  char text[64];
  // Whole numbers as users write them (4000000, not 4e+06), up to 2^53.
  if (v == std::floor(v) && std::fabs(v) < 9007199254740992.0) {
    std::snprintf(text, sizeof text, "%.0f", v);
    return text;
  }
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

}  // namespace

void parseSetting(const std::string& option, const SettingValue& value, const std::string& text) {
  std::visit(
      Overloaded{[&](double* v) { *v = number(option, text); },
                 [&](float* v) { *v = static_cast<float>(number(option, text)); },
                 [&](int* v) { *v = integer(option, text); },
                 [&](bool* v) { *v = truth(option, text); }, [&](std::string* v) { *v = text; },
                 [&](const EnumValue& v) { v.set(option, text); }},
      value);
}

std::string settingText(const SettingValue& value) {
  return std::visit(
      Overloaded{[](double* v) { return shortest(*v); }, [](float* v) { return shortest(*v); },
                 [](int* v) { return std::to_string(*v); },
                 [](bool* v) { return std::string(*v ? "true" : "false"); },
                 [](std::string* v) { return *v; }, [](const EnumValue& v) { return v.name(); }},
      value);
}

std::string keywordOf(const std::string& option) {
  std::string k = option;
  for (char& c : k)
    if (c == '-') c = '_';
  return k;
}

}  // namespace rangefuse
