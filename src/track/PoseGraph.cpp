#include "PoseGraph.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>

namespace rangefuse::internal {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// The adjoint of `p` on twists (translation, rotation): p exp(x) p^-1 = exp(Ad(p) x).
Matrix6d adjoint(const Pose& p) {
  Matrix6d a = Matrix6d::Zero();
  a.topLeftCorner<3, 3>() = p.R;
  a.topRightCorner<3, 3>() = skew(p.t) * p.R;
  a.bottomRightCorner<3, 3>() = p.R;
  return a;
}

Eigen::Vector3d rotationVector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd a(R);
  return a.angle() * a.axis();
}

/// Adds block (a, b) of a 6 x 6 matrix to the triplets of the reduced system, whose node k
/// (k >= 1) takes rows 6 (k - 1)...; node 0 is fixed and has none.
void addBlock(std::vector<Eigen::Triplet<double>>& t, size_t a, size_t b, const Matrix6d& m) {
  if (a == 0 || b == 0) return;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
      t.emplace_back(static_cast<int>(6 * (a - 1)) + r, static_cast<int>(6 * (b - 1)) + c, m(r, c));
}

}  // namespace

Pose twistPose(const Vector6d& twist) {
  const Eigen::Vector3d w = twist.tail<3>();
  const double angle = w.norm();
  Pose p;
  if (angle > 0) p.R = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  p.t = twist.head<3>();
  return p;
}

Vector6d edgeError(const PoseEdge& e, const std::vector<Pose>& poses) {
  const Pose E = e.measured.inverse() * relative(poses[e.from], poses[e.to]);
  Vector6d v;
  v << E.t, rotationVector(E.R);
  return v;
}

double graphCost(const std::vector<Pose>& poses, const std::vector<PoseEdge>& edges) {
  double cost = 0;
  for (const PoseEdge& e : edges) {
    const Vector6d r = edgeError(e, poses);
    cost += r.dot(e.information * r);
  }
  return cost;
}

double optimisePoseGraph(std::vector<Pose>& poses, const std::vector<PoseEdge>& edges,
                         int iterations, double tolerance) {
  const size_t n = poses.size();
  if (n < 2) return graphCost(poses, edges);
  const int unknowns = static_cast<int>(6 * (n - 1));
  for (int it = 0; it < iterations; ++it) {
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(unknowns);
    for (const PoseEdge& e : edges) {
      // With poses[to] -> poses[to] exp(dj) the error moves by dj; with poses[from] ->
      // poses[from] exp(di) by -Ad(poses[to]^-1 poses[from]) di (to first order).
      const Vector6d r = edgeError(e, poses);
      const Matrix6d Ji = -adjoint(relative(poses[e.to], poses[e.from]));
      const Matrix6d& W = e.information;
      addBlock(triplets, e.from, e.from, Ji.transpose() * W * Ji);
      addBlock(triplets, e.from, e.to, Ji.transpose() * W);
      addBlock(triplets, e.to, e.from, W * Ji);
      addBlock(triplets, e.to, e.to, W);
      if (e.from > 0) b.segment<6>(static_cast<int>(6 * (e.from - 1))) -= Ji.transpose() * W * r;
      if (e.to > 0) b.segment<6>(static_cast<int>(6 * (e.to - 1))) -= W * r;
    }
    Eigen::SparseMatrix<double> H(unknowns, unknowns);
    H.setFromTriplets(triplets.begin(), triplets.end());
    // A node no edge reaches (or a direction none pins) stays where it is.
    for (int k = 0; k < unknowns; ++k) H.coeffRef(k, k) += 1e-9;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
    if (solver.info() != Eigen::Success) break;
    const Eigen::VectorXd step = solver.solve(b);
    double largest = 0;
    for (size_t k = 1; k < n; ++k) {
      const Vector6d d = step.segment<6>(static_cast<int>(6 * (k - 1)));
      poses[k] = poses[k] * twistPose(d);
      largest = std::max(largest, d.cwiseAbs().maxCoeff());
    }
    if (largest < tolerance) break;
  }
  return graphCost(poses, edges);
}

}  // namespace rangefuse::internal
