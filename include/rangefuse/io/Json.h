// JSON files (run reports, scanner ground truth, eval results).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "rangefuse/core/Pose.h"

namespace rangefuse::io {

/// Writes pretty-printed JSON atomically (temporary name, then rename).
void writeJson(const std::string& path, const nlohmann::json& value);

/// Reads a JSON file; throws InputError naming the file on a parse error.
nlohmann::json readJson(const std::string& path);

/// A pose as {"rotation": 3x3 rows, "translation": [x, y, z]}.
nlohmann::json poseToJson(const Pose& pose);

/// A pose as the 12 numbers checkpoints keep: R column by column, then t (bit-exact).
nlohmann::json poseNumbers(const Pose& pose);

/// The pose of poseNumbers; throws std::runtime_error when there are not 12 numbers or they
/// are not a rigid transform.
Pose poseFromNumbers(const nlohmann::json& numbers);

}  // namespace rangefuse::io
