#include "rangefuse/io/Conf.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {
namespace {

/// The Stanford files store the conjugate of the scan-to-world rotation (NOTES.md).
Pose poseFromConf(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  Pose p;
  p.R = q.normalized().toRotationMatrix().transpose();
  p.t = t;
  return p;
}

ConfScan parseBmesh(std::istringstream& in, const std::string& where, const std::string& dir) {
  ConfScan s;
  double v[7];
  in >> s.name;
  for (double& x : v) in >> x;
  std::string extra;
  if (!in || s.name.empty())
    throw InputError(where + ": expected 'bmesh FILE tx ty tz qx qy qz qw'");
  if (in >> extra) throw InputError(where + ": extra text '" + extra + "' after bmesh pose");
  for (double x : v)
    if (!std::isfinite(x)) throw InputError(where + ": pose has a NaN or Inf value");
  Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
  if (q.norm() < 1e-6) throw InputError(where + ": quaternion has zero length");
  s.pose = poseFromConf(Eigen::Vector3d(v[0], v[1], v[2]), q);
  std::filesystem::path p(s.name);
  s.path = p.is_absolute() ? s.name : (std::filesystem::path(dir) / p).lexically_normal().string();
  return s;
}

}  // namespace

ConfFile parseConf(const std::string& path, std::istream& in) {
  const std::string dir = std::filesystem::path(path).parent_path().string();
  ConfFile conf;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    for (char& c : line)
      if (c == '\r' || c == '\t') c = ' ';
    std::istringstream words(line);
    std::string key;
    if (!(words >> key) || key[0] == '#' || key == "camera") continue;
    const std::string where = path + ": line " + std::to_string(n);
    if (key == "bmesh")
      conf.scans.push_back(parseBmesh(words, where, dir));
    else if (key == "mesh")
      conf.warnings.push_back(where + ": 'mesh' line skipped");
    else
      throw InputError(where + ": unknown keyword '" + key + "'");
  }
  if (conf.scans.empty()) throw InputError(path + ": no 'bmesh' lines: nothing to fuse");
  return conf;
}

ConfFile readConf(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  return parseConf(path, in);
}

std::string nameFor(const std::string& name, const std::string& path, const std::string& confPath) {
  namespace fs = std::filesystem;
  if (fs::path(name).is_absolute()) return name;
  // A PTX scan's name is FILE.ptx#K and its path the file's.
  const size_t hash = name.rfind('#');
  const std::string suffix =
      hash != std::string::npos && path.find('#') == std::string::npos ? name.substr(hash) : "";
  const fs::path target = fs::absolute(path).lexically_normal();
  // absolute() first: a bare name's parent is empty, which absolute() refuses.
  const fs::path dir = fs::absolute(confPath).lexically_normal().parent_path();
  const fs::path relative = target.lexically_relative(dir);
  return (relative.empty() ? target : relative).string() + suffix;
}

void writeConf(const std::string& path, const std::vector<ConfScan>& scans) {
  writeAtomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (const auto& s : scans) {
      Eigen::Quaterniond q(Eigen::Matrix3d(s.pose.R.transpose()));
      out << "bmesh " << (s.path.empty() ? s.name : nameFor(s.name, s.path, path)) << ' '
          << s.pose.t.x() << ' ' << s.pose.t.y() << ' ' << s.pose.t.z() << ' ' << q.x() << ' '
          << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
    }
  });
}

}  // namespace rangefuse::io
