#include "rangefuse/io/Json.h"

#include <fstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {

void writeJson(const std::string& path, const nlohmann::json& value) {
  writeAtomically(path, [&](std::ostream& out) { out << value.dump(2) << '\n'; });
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // parse errors, and numbers out of range
    throw InputError(path + ": not valid JSON: " + e.what());
  }
}

nlohmann::json poseToJson(const Pose& pose) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rows.push_back({pose.R(r, 0), pose.R(r, 1), pose.R(r, 2)});
  return {{"rotation", rows}, {"translation", {pose.t.x(), pose.t.y(), pose.t.z()}}};
}

nlohmann::json poseNumbers(const Pose& pose) {
  std::vector<double> v(pose.R.data(), pose.R.data() + 9);
  v.insert(v.end(), pose.t.data(), pose.t.data() + 3);
  return v;
}

Pose poseFromNumbers(const nlohmann::json& numbers) {
  const auto d = numbers.get<std::vector<double>>();
  if (d.size() != 12)
    throw std::runtime_error("a pose has " + std::to_string(d.size()) + " numbers, not 12");
  Pose p;
  p.R = Eigen::Map<const Eigen::Matrix3d>(d.data());
  p.t = Eigen::Vector3d(d[9], d[10], d[11]);
  if (!p.t.allFinite() || !rotationProblem(p.R).empty())
    throw std::runtime_error("a pose is not a rigid transform");
  return p;
}

}  // namespace rangefuse::io
