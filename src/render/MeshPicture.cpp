#include "rangefuse/render/MeshPicture.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

/// A vertex on the picture: pixel coordinates and depth (NaN when it cannot be drawn).
using Projected = Eigen::Vector3d;

/// Projects the part's vertices for the view; for the orbit view the frame fits the whole
/// mesh, found collectively.
std::vector<Projected> projectVertices(const TriangleMesh& mesh, const ViewSettings& view,
                                       MPI_Comm comm) {
  std::vector<Projected> out(mesh.vertices.size());
  if (view.camera) {
    const Pose& cam = *view.camera;
    const double nearest = 0.01 * view.farthest;
    for (size_t i = 0; i < out.size(); ++i) {
      const Eigen::Vector3d q = cam.R.transpose() * (mesh.vertices[i] - cam.t);
      out[i] = q.z() < nearest ? Projected::Constant(NAN)
                               : Projected(0.5 * view.width + view.focal * q.x() / q.z(),
                                           0.5 * view.height + view.focal * q.y() / q.z(), q.z());
    }
    return out;
  }
  const Eigen::Matrix3d axes = viewAxes(view);
  Eigen::AlignedBox3d mine;
  for (const Eigen::Vector3d& v : mesh.vertices) mine.extend(axes * v);
  const ViewFrame frame(view, mpi::unitedBox(mine, comm));
  for (size_t i = 0; i < out.size(); ++i) out[i] = frame.project(mesh.vertices[i]);
  return out;
}

/// Twice the signed area of (a, b, p), computed from the endpoints in one fixed order so that
/// the two faces sharing an edge get exactly opposite values.
double edgeFunction(const Projected& a, const Projected& b, double px, double py) {
  const bool flip = std::tie(b.x(), b.y()) < std::tie(a.x(), a.y());
  const Projected& s = flip ? b : a;
  const Projected& e = flip ? a : b;
  const double v = (px - s.x()) * (e.y() - s.y()) - (py - s.y()) * (e.x() - s.x());
  return flip ? -v : v;
}

/// Whether a pixel exactly on edge a -> b belongs to this face: of the two faces sharing an
/// edge, which traverse it in opposite directions, exactly one.
bool ownsEdge(const Projected& a, const Projected& b) {
  return b.y() > a.y() || (b.y() == a.y() && b.x() < a.x());
}

uint32_t packed(const Colour& c) {
  return uint32_t(colourByte(c[0])) << 16 | uint32_t(colourByte(c[1])) << 8 | colourByte(c[2]);
}

/// Depth and packed colour per pixel of this rank's faces.
struct DepthBuffer {
  std::vector<double> depth;
  std::vector<uint32_t> colour;
  int width;

  DepthBuffer(int w, int h)
      : depth(size_t(w) * h, std::numeric_limits<double>::infinity()),
        colour(size_t(w) * h, UINT32_MAX),
        width(w) {}

  void put(int x, int y, double z, uint32_t c) {
    const size_t i = size_t(y) * width + x;
    if (z < depth[i] || (z == depth[i] && c < colour[i])) depth[i] = z, colour[i] = c;
  }
};

/// The shade of a face: its colour (or a warm grey) by how squarely it faces the eye, a cool
/// grey when seen from behind.
Colour faceColour(const Eigen::Vector3d& normal, const Eigen::Vector3d& towardEye,
                  const Colour& base) {
  const double facing = normal.dot(towardEye);
  if (facing < 0) return Colour(0.42f, 0.46f, 0.52f) * float(0.35 - 0.45 * facing);
  return base * float(0.15 + 0.85 * facing);
}

void drawFace(const TriangleMesh& mesh, const Triangle& f, const std::vector<Projected>& p,
              const ViewSettings& view, DepthBuffer& buffer) {
  Projected a = p[f[0]], b = p[f[1]], c = p[f[2]];
  if (std::isnan(a.z()) || std::isnan(b.z()) || std::isnan(c.z())) return;
  const Eigen::Vector3d &va = mesh.vertices[f[0]], &vb = mesh.vertices[f[1]],
                        &vc = mesh.vertices[f[2]];
  const Eigen::Vector3d normal = (vb - va).cross(vc - va).normalized();
  const Eigen::Vector3d eye = view.camera ? Eigen::Vector3d((view.camera->t - va).normalized())
                                          : Eigen::Vector3d(viewAxes(view).row(2).transpose());
  const bool coloured = !mesh.colours.empty();
  Colour base = Colour(235, 225, 205) / 255;
  if (coloured) base = (mesh.colours[f[0]] + mesh.colours[f[1]] + mesh.colours[f[2]]) / 3;
  const uint32_t colour = packed(faceColour(normal, eye, base));
  double area = edgeFunction(a, b, c.x(), c.y());
  if (area == 0 || !std::isfinite(area)) return;
  if (area < 0) std::swap(b, c), area = -area;
  const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()}))));
  const int x1 = std::min(view.width - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))));
  const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()}))));
  const int y1 = std::min(view.height - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))));
  const bool ownBC = ownsEdge(b, c), ownCA = ownsEdge(c, a), ownAB = ownsEdge(a, b);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double wa = edgeFunction(b, c, px, py), wb = edgeFunction(c, a, px, py),
                   wc = edgeFunction(a, b, px, py);
      if (wa < 0 || wb < 0 || wc < 0) continue;
      if ((wa == 0 && !ownBC) || (wb == 0 && !ownCA) || (wc == 0 && !ownAB)) continue;
      buffer.put(x, y, (wa * a.z() + wb * b.z() + wc * c.z()) / area, colour);
    }
}

}  // namespace

Image pictureOfMesh(const MeshPart& part, const ViewSettings& view, int root, MPI_Comm comm) {
  const std::vector<Projected> p = projectVertices(part.mesh, view, comm);
  DepthBuffer buffer(view.width, view.height);
  for (const Triangle& f : part.mesh.faces) drawFace(part.mesh, f, p, view, buffer);
  // The nearest depth of every pixel, then the least colour among the ranks reaching it.
  std::vector<double> nearest(buffer.depth.size());
  MPI_Allreduce(buffer.depth.data(), nearest.data(), int(nearest.size()), MPI_DOUBLE, MPI_MIN,
                comm);
  for (size_t i = 0; i < nearest.size(); ++i)
    if (buffer.depth[i] != nearest[i]) buffer.colour[i] = UINT32_MAX;
  std::vector<uint32_t> colour(buffer.colour.size());
  MPI_Reduce(buffer.colour.data(), colour.data(), int(colour.size()), MPI_UINT32_T, MPI_MIN, root,
             comm);
  Image img(view.width, view.height, 0);
  if (mpi::rank(comm) != root) return img;
  for (size_t i = 0; i < colour.size(); ++i)
    for (int k = 0; k < 3; ++k)
      img.rgb[3 * i + k] =
          colour[i] == UINT32_MAX ? kBackground[k] : uint8_t(colour[i] >> (8 * (2 - k)));
  return img;
}

}  // namespace rangefuse
