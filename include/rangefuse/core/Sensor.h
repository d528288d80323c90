// Where a scan's lines of sight come from: the sensor's position for a pinhole camera or a
// scanner station, or one direction for a near-orthographic grid (Cyberware).
#pragma once

#include <Eigen/Core>

#include "rangefuse/core/Pose.h"

namespace rangefuse {

struct Sensor {
  bool isPoint = false;  ///< lines of sight meet at `point`; else all run along `direction`
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  ///< toward the sensor

  /// Unit direction from p toward the sensor.
  Eigen::Vector3d toward(const Eigen::Vector3d& p) const {
    return isPoint ? Eigen::Vector3d((point - p).normalized()) : direction;
  }

  /// The same sensor moved by `pose`.
  Sensor placed(const Pose& pose) const {
    return Sensor{isPoint, pose.apply(point), pose.rotate(direction)};
  }
};

}  // namespace rangefuse
