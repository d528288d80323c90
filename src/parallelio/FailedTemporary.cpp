#include "FailedTemporary.h"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <system_error>

namespace rangefuse::io::internal {
namespace {

/// True for "<digits>-<digits>.lock": the part Open MPI appends to the file's name and a dash.
bool isLockSuffix(const std::string& s) {
  const std::string ext = ".lock";
  if (s.size() <= ext.size() || s.compare(s.size() - ext.size(), ext.size(), ext) != 0)
    return false;
  const std::string ids = s.substr(0, s.size() - ext.size());
  const size_t dash = ids.find('-');
  if (dash == 0 || dash == std::string::npos || dash + 1 == ids.size()) return false;
  for (size_t i = 0; i < ids.size(); ++i)
    if (i != dash && !std::isdigit(static_cast<unsigned char>(ids[i]))) return false;
  return true;
}

}  // namespace

void removeFailedTemporary(const std::string& tmp) {
  namespace fs = std::filesystem;
  std::remove(tmp.c_str());
  const fs::path file(tmp);
  const std::string prefix = file.filename().string() + "-";
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;  // a folder we cannot list leaves nothing more we could remove
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code ignored;
    if (name.compare(0, prefix.size(), prefix) == 0 && isLockSuffix(name.substr(prefix.size())))
      fs::remove(it->path(), ignored);
  }
}

}  // namespace rangefuse::io::internal
