#include "rangefuse/io/AtomicFile.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"

namespace rangefuse::io {

std::string temporaryPath(const std::string& path) {
  return path + ".tmp";
}

void writeAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = temporaryPath(path);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing");
    faultPoint("write", path);
    write(out);
    out.flush();
    if (!out) throw InputError(path + ": write failed (disk full?)");
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  moveIntoPlace(tmp, path);
}

void moveIntoPlace(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot rename temporary file into place: " + ec.message());
  }
}

}  // namespace rangefuse::io
