#include "rangefuse/register/ProjectiveIcp.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace rangefuse {
namespace {

/// Camera-frame points and unit normals (facing the camera) of a depth map; NaN where unknown.
struct VertexMap {
  int width = 0, height = 0;
  std::vector<Eigen::Vector3f> points, normals;
};

VertexMap vertices(const DepthMap& m) {
  VertexMap out;
  out.width = m.width, out.height = m.height;
  const size_t n = m.depth.size();
  const Eigen::Vector3f none = Eigen::Vector3f::Constant(NAN);
  out.points.assign(n, none);
  out.normals.assign(n, none);
  for (int v = 0; v < m.height; ++v)
    for (int u = 0; u < m.width; ++u) {
      const float d = m.at(u, v);
      if (d > 0)
        out.points[static_cast<size_t>(v) * m.width + u] =
            Eigen::Vector3f(static_cast<float>((u - m.cx) / m.fx * d),
                            static_cast<float>((v - m.cy) / m.fy * d), d);
    }
  for (int v = 1; v + 1 < m.height; ++v)
    for (int u = 1; u + 1 < m.width; ++u) {
      const size_t k = static_cast<size_t>(v) * m.width + u;
      const Eigen::Vector3f& l = out.points[k - 1];
      const Eigen::Vector3f& r = out.points[k + 1];
      const Eigen::Vector3f& a = out.points[k - m.width];
      const Eigen::Vector3f& b = out.points[k + m.width];
      if (!(std::isfinite(l.x()) && std::isfinite(r.x()) && std::isfinite(a.x()) &&
            std::isfinite(b.x())))
        continue;
      Eigen::Vector3f nrm = (r - l).cross(b - a);
      const float len = nrm.norm();
      if (!(len > 0)) continue;
      nrm /= len;
      if (nrm.dot(out.points[k]) > 0) nrm = -nrm;
      out.normals[k] = nrm;
    }
  return out;
}

/// exp of a twist (translation, rotation vector) applied on the left of `pose`.
Pose stepped(const Eigen::Matrix<double, 6, 1>& x, const Pose& pose) {
  const Eigen::Vector3d w = x.tail<3>();
  const double angle = w.norm();
  const Eigen::Matrix3d R = angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                      : Eigen::Matrix3d::Identity();
  return Pose{R * pose.R, R * pose.t + x.head<3>()};
}

/// One level: Gauss-Newton steps on the point-to-plane residuals of projective partners.
/// Returns the share of `current`'s points that found a partner at the last step.
double alignLevel(const DepthMap& prevMap, const VertexMap& prev, const VertexMap& cur,
                  const ProjectiveIcpSettings& s, Pose& motion) {
  const double cosLimit = std::cos(s.maxNormalAngleDeg * M_PI / 180);
  double share = 0;
  for (int it = 0; it < s.iterations; ++it) {
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    size_t points = 0, partners = 0;
    double depthSum = 0;
    for (size_t k = 0; k < cur.points.size(); ++k) {
      const Eigen::Vector3f& pc = cur.points[k];
      const Eigen::Vector3f& nc = cur.normals[k];
      if (!std::isfinite(pc.x()) || !std::isfinite(nc.x())) continue;
      ++points;
      const Eigen::Vector3d p = motion.apply(pc.cast<double>());
      if (!(p.z() > 0)) continue;
      const int u = static_cast<int>(std::lround(prevMap.fx * p.x() / p.z() + prevMap.cx));
      const int v = static_cast<int>(std::lround(prevMap.fy * p.y() / p.z() + prevMap.cy));
      if (u < 0 || v < 0 || u >= prev.width || v >= prev.height) continue;
      const size_t j = static_cast<size_t>(v) * prev.width + u;
      const Eigen::Vector3f& qf = prev.points[j];
      const Eigen::Vector3f& nf = prev.normals[j];
      if (!std::isfinite(qf.x()) || !std::isfinite(nf.x())) continue;
      const Eigen::Vector3d q = qf.cast<double>(), n = nf.cast<double>();
      if ((p - q).norm() > s.maxDistance || n.dot(motion.R * nc.cast<double>()) < cosLimit)
        continue;
      const double r = n.dot(p - q);
      const double w = std::abs(r) > s.huber ? s.huber / std::abs(r) : 1.0;
      Eigen::Matrix<double, 6, 1> J;
      J.head<3>() = n;
      J.tail<3>() = p.cross(n);
      A += w * J * J.transpose();
      b -= w * r * J;
      depthSum += q.z();
      ++partners;
    }
    share = points ? static_cast<double>(partners) / points : 0;
    if (partners < 6) return 0;
    const Eigen::Matrix<double, 6, 1> x = solveWellPosed(A, b, depthSum / partners);
    if (!x.allFinite()) return 0;
    motion = stepped(x, motion);
    if (x.tail<3>().norm() < 1e-6 && x.head<3>().norm() < 1e-6 * s.maxDistance) break;
  }
  return share;
}

}  // namespace

Eigen::Matrix<double, 6, 1> solveWellPosed(const Eigen::Matrix<double, 6, 6>& A,
                                           const Eigen::Matrix<double, 6, 1>& b, double length) {
  constexpr double kWeak = 1e-3;
  Eigen::Matrix<double, 6, 1> scale;
  scale << 1, 1, 1, 1 / length, 1 / length, 1 / length;
  const Eigen::Matrix<double, 6, 6> As = scale.asDiagonal() * A * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(As);
  const auto& values = eigen.eigenvalues();
  const auto& vectors = eigen.eigenvectors();
  const Eigen::Matrix<double, 6, 1> bs = scale.asDiagonal() * b;
  Eigen::Matrix<double, 6, 1> y = Eigen::Matrix<double, 6, 1>::Zero();
  for (int k = 0; k < 6; ++k)
    if (values[k] > kWeak * values[5]) y += vectors.col(k) * (vectors.col(k).dot(bs) / values[k]);
  return scale.asDiagonal() * y;
}

DepthMap halve(const DepthMap& m) {
  DepthMap out;
  out.width = m.width / 2, out.height = m.height / 2;
  out.fx = m.fx / 2, out.fy = m.fy / 2;
  out.cx = (m.cx - 0.5) / 2, out.cy = (m.cy - 0.5) / 2;
  out.depth.assign(static_cast<size_t>(out.width) * out.height, 0.0f);
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u) {
      float first = 0, sum = 0;
      int count = 0;
      for (int dv = 0; dv < 2; ++dv)
        for (int du = 0; du < 2; ++du) {
          const float d = m.at(2 * u + du, 2 * v + dv);
          if (!(d > 0)) continue;
          if (first == 0) first = d;
          if (std::abs(d - first) > 0.03f * first) continue;
          sum += d, ++count;
        }
      if (count) out.depth[static_cast<size_t>(v) * out.width + u] = sum / count;
    }
  return out;
}

FrameAlignment alignFrames(const DepthMap& previous, const DepthMap& current, const Pose& guess,
                           const ProjectiveIcpSettings& s) {
  std::vector<DepthMap> prev{previous}, cur{current};
  for (int l = 1; l < s.levels; ++l)
    prev.push_back(halve(prev.back())), cur.push_back(halve(cur.back()));
  FrameAlignment out;
  out.motion = guess;
  for (int l = s.levels - 1; l >= s.skipFinest; --l) {
    ProjectiveIcpSettings level = s;
    // Coarser levels reach farther: their pixels span more of the scene.
    level.maxDistance = s.maxDistance * std::ldexp(1.0, l - s.skipFinest);
    out.share = alignLevel(prev[l], vertices(prev[l]), vertices(cur[l]), level, out.motion);
    if (out.share <= 0) return FrameAlignment{false, guess, 0};
  }
  out.ok = out.share >= s.minShare;
  if (!out.ok) out.motion = guess;
  return out;
}

}  // namespace rangefuse
