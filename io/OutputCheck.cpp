#include "rangefuse/io/OutputCheck.h"

#include <sys/statvfs.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <filesystem>

#include "rangefuse/core/Error.h"

namespace rangefuse::io {
namespace {

namespace fs = std::filesystem;

std::string folderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

std::string mebibytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f MiB", bytes / (1024.0 * 1024.0));
  return text;
}

}  // namespace

void checkWritable(const std::string& path, const std::string& what) {
  const std::string folder = folderOf(path);
  std::error_code ec;
  const std::string where = path + ": cannot write the " + what + " there: ";
  if (!fs::exists(folder, ec)) throw InputError(where + "folder '" + folder + "' does not exist");
  if (!fs::is_directory(folder, ec)) throw InputError(where + "'" + folder + "' is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw InputError(where + "folder '" + folder + "' is not writable");
  if (fs::is_directory(path, ec)) throw InputError(where + "it is a folder");
  if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0)
    throw InputError(where + "the file exists and is not writable");
}

void requireExtension(const std::string& path, const std::string& what,
                      const std::vector<std::string>& extensions) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string list;
  for (const std::string& e : extensions) {
    if (ext == e) return;
    list += (list.empty() ? "" : " or ") + e;
  }
  throw InputError(path + ": the " + what + " is written as " + list + "; name it so (" +
                   (ext.empty() ? "no extension" : "'" + ext + "'") + " is not written)");
}

int64_t freeBytes(const std::string& path) {
  struct statvfs s;
  if (::statvfs(folderOf(path).c_str(), &s) != 0) return -1;
  return static_cast<int64_t>(s.f_bavail) * static_cast<int64_t>(s.f_frsize);
}

std::string spaceWarning(const std::string& path, uint64_t bytes, const std::string& what) {
  const int64_t free = freeBytes(path);
  if (free < 0 || static_cast<uint64_t>(free) >= bytes) return "";
  return path + ": the " + what + " needs about " + mebibytes(static_cast<double>(bytes)) +
         " but only " + mebibytes(static_cast<double>(free)) + " are free there";
}

}  // namespace rangefuse::io
