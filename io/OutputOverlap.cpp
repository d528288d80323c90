#include "rangefuse/io/OutputOverlap.h"

#include <sys/stat.h>

#include <filesystem>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {
namespace {

namespace fs = std::filesystem;

std::optional<FilePlace> statPlace(const std::string& path, const std::string& name) {
  struct stat s;
  if (::stat(path.c_str(), &s) != 0) return std::nullopt;
  return FilePlace{s.st_dev, s.st_ino, name};
}

/// "'a.ply' (the mesh)".
std::string named(const RolePath& r) {
  return "'" + r.path + "' (the " + r.role + ")";
}

}  // namespace

std::optional<FilePlace> placeOf(const std::string& path) {
  if (path.empty()) return std::nullopt;
  if (auto existing = statPlace(path, "")) return existing;
  // A dangling symbolic link is written through: the file it points at is the one made.
  std::error_code ec;
  fs::path target = path;
  if (fs::is_symlink(target, ec)) {
    const fs::path link = fs::read_symlink(target, ec);
    if (!ec) target = link.is_absolute() ? link : fs::path(path).parent_path() / link;
  }
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  return statPlace(folder.string(), target.filename().string());
}

bool sameFile(const std::string& a, const std::string& b) {
  const auto pa = placeOf(a), pb = placeOf(b);
  return pa && pb && *pa == *pb;
}

bool inside(const std::string& path, const std::string& folder) {
  const auto home = statPlace(folder, "");
  if (!home) return false;
  std::error_code ec;
  // Walk up from the file's folder (links resolved) to the root, looking for `folder`.
  fs::path at = fs::weakly_canonical(fs::absolute(path, ec), ec).parent_path();
  for (;;) {
    const auto here = statPlace(at.string(), "");
    if (here && *here == *home) return true;
    if (at == at.root_path() || at.empty()) return false;
    at = at.parent_path();
  }
}

void refuseOverlaps(const FileRoles& files) {
  std::vector<std::pair<FilePlace, const RolePath*>> read, written;
  for (const RolePath& in : files.inputs)
    if (const auto place = placeOf(in.path); place && place->name.empty())
      read.emplace_back(*place, &in);  // an input that does not exist yet cannot be overwritten
  for (const RolePath& out : files.outputs) {
    const auto place = placeOf(out.path);
    if (!place) continue;  // its folder is missing: checkWritable says so
    for (const auto& [inPlace, in] : read)
      if (inPlace == *place)
        throw InputError(out.path + ": the " + out.role + " would overwrite " + named(*in) +
                         ", which this run reads; write it elsewhere");
    for (const RolePath& folder : files.watched)
      if (!folder.path.empty() && inside(out.path, folder.path))
        throw InputError(out.path + ": the " + out.role + " would be written inside " +
                         named(folder) + ", whose new files are read as frames; write it " +
                         "elsewhere");
    for (const auto& [otherPlace, other] : written)
      if (otherPlace == *place)
        throw InputError(out.path + ": given as both " + named(*other) + " and the " + out.role +
                         "; give each its own file");
    written.emplace_back(*place, &out);
  }
}

std::vector<std::string> filesUnder(const std::string& folder) {
  std::vector<std::string> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(
           folder, fs::directory_options::follow_directory_symlink, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back(it->path().string());
  return files;
}

std::vector<RolePath> outputWithTemporary(const std::string& role, const std::string& path) {
  if (path.empty()) return {};
  return {{role, path}, {"temporary file of the " + role, temporaryPath(path)}};
}

}  // namespace rangefuse::io
