// The Python module `rangefuse`: the library's Fusion (rangefuse/rangefuse.h) over numpy arrays.
// Arrays come in as they are laid out where the library's structs allow (depth counts), are
// copied once into its grids where they do not, and the mesh goes out without a copy: each
// array is a view of the library's own vector, kept alive by the array. docs/python.md.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Limits.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/DepthPng.h"
#include "rangefuse/io/Jpeg.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/rangefuse.h"

namespace py = pybind11;

namespace rangefuse::python {
namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Bytes = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>;

/// "shape (4, 4)" of an array, or "of that type" for what could not become one.
std::string shapeOf(const py::array& a) {
  if (!a) return "of that type";
  std::string s = "shape (";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// A 4 x 4 rigid transform (last row 0 0 0 1) as a Pose; `what` names it in errors.
Pose poseOf(const py::handle& given, const std::string& what) {
  const Doubles m = Doubles::ensure(given);
  if (!m || m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4)
    throw InputError(what + ": a pose must be a 4 x 4 matrix, not " + shapeOf(m));
  const auto v = m.unchecked<2>();
  Pose p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.R(r, c) = v(r, c);
    p.t[r] = v(r, 3);
  }
  if (v(3, 0) != 0 || v(3, 1) != 0 || v(3, 2) != 0 || v(3, 3) != 1)
    throw InputError(what + ": a pose's last row must be 0 0 0 1");
  return p;
}

/// fx, fy, cx, cy of a 3 x 3 camera matrix.
Pinhole pinholeOf(const py::handle& given, const std::string& what) {
  const Doubles k = Doubles::ensure(given);
  if (!k || k.ndim() != 2 || k.shape(0) != 3 || k.shape(1) != 3)
    throw InputError(what + ": intrinsics must be a 3 x 3 camera matrix, not " + shapeOf(k));
  const auto v = k.unchecked<2>();
  const Pinhole p{v(0, 0), v(1, 1), v(0, 2), v(1, 2)};
  if (!(p.fx > 0) || !(p.fy > 0) || !std::isfinite(p.cx) || !std::isfinite(p.cy))
    throw InputError(what + ": intrinsics need positive focal lengths and a finite centre");
  return p;
}

/// An RGB image (height, width, 3) of bytes.
Image imageOf(const py::handle& given, const std::string& what) {
  const Bytes a = Bytes::ensure(given);
  if (!a || a.ndim() != 3 || a.shape(2) != 3)
    throw InputError(what + ": a colour image must be (height, width, 3) bytes, not " + shapeOf(a));
  Image image;
  image.width = static_cast<int>(a.shape(1)), image.height = static_cast<int>(a.shape(0));
  image.rgb.assign(a.data(), a.data() + a.size());
  return image;
}

/// A grid of points (rows, cols, 3), NaN where nothing was measured, with colours (rows, cols,
/// 3) bytes when given.
RangeGrid gridOf(const py::handle& points, const py::handle& colours, const std::string& what) {
  const Doubles a = Doubles::ensure(points);
  if (!a || a.ndim() != 3 || a.shape(2) != 3)
    throw InputError(what + ": points must be (rows, cols, 3), not " + shapeOf(a));
  RangeGrid g;
  g.rows = static_cast<int>(a.shape(0)), g.cols = static_cast<int>(a.shape(1));
  g.cell.assign(a.size() / 3, -1);
  const double* p = a.data();
  for (size_t i = 0; i < g.cell.size(); ++i, p += 3)
    if (!std::isnan(p[0]) && !std::isnan(p[1]) && !std::isnan(p[2]))
      g.cell[i] = static_cast<int32_t>(g.points.size()), g.points.emplace_back(p[0], p[1], p[2]);
  if (colours.is_none()) return g;
  const Image c = imageOf(colours, what);
  if (c.height != g.rows || c.width != g.cols)
    throw InputError(what + ": colours are " + std::to_string(c.height) + " x " +
                     std::to_string(c.width) + ", the points " + std::to_string(g.rows) + " x " +
                     std::to_string(g.cols));
  for (size_t i = 0; i < g.cell.size(); ++i)
    if (g.cell[i] >= 0)
      g.colours.push_back(Colour(c.rgb[3 * i], c.rgb[3 * i + 1], c.rgb[3 * i + 2]) / 255);
  g.colourKind = ColourKind::rgb;
  return g;
}

/// Depth counts (height, width): integers of any width as counts (uint16 as a depth PNG holds
/// them, int32 as PIL gives them), floats as metres scaled by `scale` counts a metre; any other
/// dtype is refused by name.
io::DepthImage depthOf(const py::handle& given, double scale, const std::string& what) {
  const py::array any = py::array::ensure(given);
  if (!any || any.ndim() != 2)
    throw InputError(what + ": depth must be (height, width), not " + shapeOf(any));
  io::DepthImage d;
  d.height = static_cast<int>(any.shape(0)), d.width = static_cast<int>(any.shape(1));
  const char kind = any.dtype().kind();
  const std::string dtype = py::str(any.dtype());
  if (kind == 'u' || kind == 'i') {
    const auto c = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(given);
    d.counts.resize(c.size());
    for (py::ssize_t i = 0; i < c.size(); ++i) {
      const int64_t counts = c.data()[i];
      if (counts < 0 || counts > 65535)
        throw InputError(what + ": depth count " + std::to_string(counts) + " (" + dtype +
                         ") is outside a depth image's 0 to 65535 (integers are counts, " +
                         "depth_scale a metre; give metres as floats)");
      d.counts[i] = static_cast<uint16_t>(counts);
    }
    return d;
  }
  if (kind != 'f')
    throw InputError(what + ": depth of dtype " + dtype +
                     " is neither counts (an integer dtype) nor metres (a float dtype)");
  const Doubles m = Doubles::ensure(given);
  d.counts.resize(m.size());
  for (py::ssize_t i = 0; i < m.size(); ++i) {
    const double metres = m.data()[i], counts = metres * scale;
    if (!(counts >= 0 && counts <= 65535))  // NaN too
      throw InputError(what + ": depth " + std::to_string(metres) + " m (" + dtype + ") is " +
                       (metres < 0 || std::isnan(metres)
                            ? "not a distance (0 for none)"
                            : "beyond the " + std::to_string(65535 / scale) +
                                  " m that depth_scale " + std::to_string(scale) +
                                  " counts a metre can hold"));
    d.counts[i] = static_cast<uint16_t>(std::lround(counts));
  }
  return d;
}

/// A numpy view of `values` (rows of `width` scalars), owning them.
template <class Scalar, class Vector>
py::array viewOf(std::vector<Vector>&& values, py::ssize_t width) {
  auto* owned = new std::vector<Vector>(std::move(values));
  py::capsule free(owned, [](void* v) { delete static_cast<std::vector<Vector>*>(v); });
  static_assert(sizeof(Vector) % sizeof(Scalar) == 0);
  return py::array_t<Scalar>({static_cast<py::ssize_t>(owned->size()), width},
                             reinterpret_cast<const Scalar*>(owned->data()), free);
}

/// Sets a setting from a Python value of its type (enumerations by name).
void setFromPython(const std::string& option, const SettingValue& value, const py::handle& v) {
  std::visit(
      Overloaded{[&](auto* member) { *member = v.cast<std::remove_pointer_t<decltype(member)>>(); },
                 [&](const EnumValue& e) { e.set(option, v.cast<std::string>()); }},
      value);
}

/// A field from Fusion's keywords: the field's settings by their options' names with '_' for
/// '-' (FieldSettings::settings()), and max_voxels (--max-voxels).
FieldSettings fieldOf(double voxel, const std::string& method, const py::kwargs& more) {
  FieldSettings f;
  f.voxel = voxel;
  f.method = parseFieldMethod("method", method);
  std::vector<std::string> keywords = {"max_voxels"};
  for (const Setting<FieldSettings>& s : FieldSettings::settings())
    if (s.option != "voxel" && s.option != "method") keywords.push_back(keywordOf(s.option));
  for (const auto& [key, value] : more) {
    const std::string k = py::str(key);
    if (k == "max_voxels") {
      f.maxVoxels = value.cast<uint64_t>();
      continue;
    }
    const auto& table = FieldSettings::settings();
    const auto s = std::find_if(table.begin(), table.end(), [&](const Setting<FieldSettings>& s) {
      return keywordOf(s.option) == k && s.option != "voxel" && s.option != "method";
    });
    if (s == table.end()) {
      std::string known;
      for (const std::string& w : keywords) known += (known.empty() ? "" : ", ") + w;
      throw InputError("Fusion: unknown setting '" + k + "' (settings: " + known + ")");
    }
    setFromPython(s->option, s->value(f), value);
  }
  return f;
}

/// A depth limit given by its name, depth_max, or by its old one (warned about).
double depthMaxOf(double depthMax, const py::object& old, const char* oldName) {
  if (old.is_none()) return depthMax;
  py::module_::import("warnings")
      .attr("warn")(
          std::string(oldName) + " is now depth_max (as --depth-max); " + oldName + " will go",
          py::module_::import("builtins").attr("FutureWarning"), 2);
  return old.cast<double>();
}

/// A 4 x 4 numpy matrix of a pose.
py::array_t<double> matrixOf(const Pose& p) {
  py::array_t<double> out({4, 4});
  auto m = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = r == 3 ? (c == 3) : c == 3 ? p.t[r] : p.R(r, c);
  return out;
}

/// An mpi4py communicator (anything with py2f()) as an MPI_Comm; None: this process alone.
MPI_Comm commOf(const py::object& comm) {
  if (comm.is_none()) return MPI_COMM_NULL;
  if (!py::hasattr(comm, "py2f"))
    throw InputError("Fusion: comm must be an mpi4py communicator (or None)");
  return MPI_Comm_f2c(comm.attr("py2f")().cast<MPI_Fint>());
}

std::string nameOr(const std::string& name, const Fusion& f) {
  return name.empty() ? "frame_" + std::to_string(f.frames()) : name;
}

void addGrid(Fusion& f, const py::handle& points, const py::handle& pose,
             const py::handle& intrinsics, bool station, const py::handle& colours,
             const std::string& name) {
  const std::string n = nameOr(name, f);
  RangeGrid g = gridOf(points, colours, n);
  if (!intrinsics.is_none()) g.pinhole = pinholeOf(intrinsics, n);
  g.spherical = station;
  const Pose p = poseOf(pose, n);
  py::gil_scoped_release free;
  f.addGrid(std::move(g), p, n);
}

void addDepth(Fusion& f, const py::handle& depth, const py::handle& intrinsics,
              const py::handle& pose, const py::handle& colour, double scale, double depthMax,
              const py::object& depthTrunc, const std::string& name) {
  const std::string n = nameOr(name, f);
  const double trunc = depthMaxOf(depthMax, depthTrunc, "depth_trunc");
  if (!(scale > 0)) throw InputError(n + ": depth_scale must be positive counts per unit");
  io::DepthImage d = depthOf(depth, scale, n);
  const Pinhole k = pinholeOf(intrinsics, n);
  const io::DepthCamera camera{k.fx, k.fy, k.cx, k.cy, d.width, d.height, 1 / scale, trunc};
  const Pose p = poseOf(pose, n);
  std::unique_ptr<Image> c;
  if (!colour.is_none()) c = std::make_unique<Image>(imageOf(colour, n));
  py::gil_scoped_release free;
  f.addDepth(std::move(d), camera, p, c.get(), n);
}

py::dict trackDepth(Fusion& f, const py::handle& depth, const py::handle& intrinsics,
                    const py::handle& colour, double scale, double depthMax,
                    const py::object& depthTrunc, const py::object& time, const std::string& name) {
  const std::string n = nameOr(name, f);
  const double trunc = depthMaxOf(depthMax, depthTrunc, "depth_trunc");
  if (!(scale > 0)) throw InputError(n + ": depth_scale must be positive counts per unit");
  io::DepthImage d = depthOf(depth, scale, n);
  const Pinhole k = pinholeOf(intrinsics, n);
  const io::DepthCamera camera{k.fx, k.fy, k.cx, k.cy, d.width, d.height, 1 / scale, trunc};
  std::unique_ptr<Image> c;
  if (!colour.is_none()) c = std::make_unique<Image>(imageOf(colour, n));
  const double t = time.is_none() ? NAN : time.cast<double>();
  TrackedFrame r;
  {
    py::gil_scoped_release free;
    r = f.track(std::move(d), camera, c.get(), t, n);
  }
  py::dict out;
  out["pose"] = matrixOf(r.cameraToWorld);
  out["fused"] = r.fused;
  out["inliers"] = r.inliers;
  out["rms"] = r.rms;
  out["why"] = r.why;
  return out;
}

py::tuple meshOf(Fusion& f) {
  TriangleMesh m;
  {
    py::gil_scoped_release free;
    m = f.mesh();
  }
  const bool coloured = !m.colours.empty();
  py::object colours = py::none();
  if (coloured) colours = viewOf<float>(std::move(m.colours), 3);
  return py::make_tuple(viewOf<double>(std::move(m.vertices), 3),
                        viewOf<int32_t>(std::move(m.faces), 3), colours);
}

/// A scan file's grid as points (rows, cols, 3), NaN where it has none, and colours (rows,
/// cols, 3) bytes or None: what add_grid takes.
py::tuple readGrid(const std::string& path) {
  io::ConfScan scan;
  scan.name = scan.path = path;
  RangeGrid g;
  {
    py::gil_scoped_release free;  // threads may read several files at once
    g = io::readScanGrid(scan);
  }
  py::array_t<double> points({g.rows, g.cols, 3});
  double* p = points.mutable_data();
  std::fill(p, p + points.size(), NAN);
  for (size_t i = 0; i < g.cell.size(); ++i)
    if (g.cell[i] >= 0)
      for (int k = 0; k < 3; ++k) p[3 * i + k] = g.points[g.cell[i]][k];
  if (g.colours.empty()) return py::make_tuple(points, py::none());
  py::array_t<uint8_t> colours({g.rows, g.cols, 3});
  uint8_t* c = colours.mutable_data();
  std::fill(c, c + colours.size(), 0);
  for (size_t i = 0; i < g.cell.size(); ++i)
    if (g.cell[i] >= 0)
      for (int k = 0; k < 3; ++k) c[3 * i + k] = colourByte(g.colours[g.cell[i]][k]);
  return py::make_tuple(points, colours);
}

/// A .conf's scans: (path, 4 x 4 pose) each, paths resolved against its folder.
py::list readConf(const std::string& path) {
  py::list out;
  for (const io::ConfScan& s : io::readConf(path).scans)
    out.append(py::make_tuple(s.path, matrixOf(s.pose)));
  return out;
}

/// A 16-bit depth PNG's counts, (height, width) uint16.
py::array_t<uint16_t> readDepth(const std::string& path) {
  io::DepthImage d;
  {
    py::gil_scoped_release free;
    d = io::readDepthPng(path, InputLimits{}.maxGridCells);
  }
  py::array_t<uint16_t> out({d.height, d.width});
  std::copy(d.counts.begin(), d.counts.end(), out.mutable_data());
  return out;
}

/// An 8-bit colour image (PNG or JPEG), (height, width, 3) bytes.
py::array_t<uint8_t> readColour(const std::string& path) {
  Image c;
  {
    py::gil_scoped_release free;
    c = io::readColourImage(path, InputLimits{}.maxGridCells);
  }
  py::array_t<uint8_t> out({c.height, c.width, 3});
  std::copy(c.rgb.begin(), c.rgb.end(), out.mutable_data());
  return out;
}

/// A depth folder's frames (TUM or Redwood): (depth path, colour path or None, 3 x 3
/// intrinsics, depth_scale, camera-to-world 4 x 4 or None without a trajectory, time) each, as
/// add_depth and track take them.
py::list readFrames(const std::string& folder) {
  const io::ConfFile conf = io::readScanList(folder);
  py::list out;
  for (const io::ConfScan& s : conf.scans) {
    if (!s.depth) throw InputError(folder + ": " + s.path + " is not a depth image");
    const io::DepthCamera& k = *s.depth;
    py::array_t<double> K({3, 3});
    auto m = K.mutable_unchecked<2>();
    const double v[3][3] = {{k.fx, 0, k.cx}, {0, k.fy, k.cy}, {0, 0, 1}};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m(r, c) = v[r][c];
    const py::object colour = s.colour.empty() ? py::object(py::none()) : py::str(s.colour);
    const py::object pose = conf.posed ? py::object(matrixOf(io::cameraPose(s.pose))) : py::none();
    out.append(py::make_tuple(s.path, colour, K, 1 / k.unit, pose, s.time));
  }
  return out;
}

}  // namespace
}  // namespace rangefuse::python

PYBIND11_MODULE(rangefuse, m) {
  using namespace rangefuse;
  using namespace rangefuse::python;
  m.doc() = "Range images fused into one mesh on MPI ranks (docs/python.md)";
  m.attr("__version__") = libraryVersion();
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::class_<Fusion>(m, "Fusion")
      .def(py::init([](double voxel, const std::string& method, const py::object& comm,
                       const py::kwargs& more) {
             return Fusion(fieldOf(voxel, method, more), commOf(comm));
           }),
           py::arg("voxel"), py::arg("method") = "prism", py::arg("comm") = py::none(),
           "A fusion at `voxel` (the scans' units) by `method` (prism, robust, consensus, naive) "
           "on an mpi4py communicator (None: this process alone); other keywords are the field's "
           "settings (envelope, brick, colour, min_views, fill_holes, threads, ...)")
      .def("add_grid", &addGrid, py::arg("points"), py::arg("pose"),
           py::arg("intrinsics") = py::none(), py::arg("station") = false,
           py::arg("colours") = py::none(), py::arg("name") = "",
           "Adds a range grid: points (rows, cols, 3) in the sensor's frame, NaN where nothing "
           "was measured, placed by the 4 x 4 pose (scan to world)")
      .def("add_depth", &addDepth, py::arg("depth"), py::arg("intrinsics"), py::arg("pose"),
           py::arg("colour") = py::none(), py::arg("depth_scale") = 1000.0,
           py::arg("depth_max") = 0.0, py::arg("depth_trunc") = py::none(), py::arg("name") = "",
           "Adds a depth image (height, width): counts of any integer dtype (uint16 as a PNG holds "
           "them, "
           "int32 as PIL gives them) or metres of a float dtype, depth_scale "
           "counts a unit; intrinsics a 3 x 3 camera matrix; pose camera to world (OpenCV axes)")
      .def(
          "add_scans",
          [](Fusion& f, const std::string& path, const std::string& format,
             const std::string& intrinsics, double depthMax, double depthScale,
             const py::object& maxDepth) {
            io::ScanSourceOptions source;
            source.format = format, source.intrinsics = intrinsics;
            source.depthMax = depthMaxOf(depthMax, maxDepth, "max_depth");
            source.depthScale = depthScale;
            py::gil_scoped_release free;
            f.addScans(path, source);
          },
          py::arg("path"), py::arg("format") = "auto", py::arg("intrinsics") = "",
          py::arg("depth_max") = 0.0, py::arg("depth_scale") = 0.0,
          py::arg("max_depth") = py::none(),
          "Adds every scan a list names, as rangefuse fuse --scans reads it (a .conf, a PTX "
          "file, a posed TUM or Redwood depth folder); each file is read when the field is "
          "built, by the rank whose share it is (under mpirun, ranks do not read each other's "
          "files)")
      .def("track", &trackDepth, py::arg("depth"), py::arg("intrinsics"),
           py::arg("colour") = py::none(), py::arg("depth_scale") = 1000.0,
           py::arg("depth_max") = 0.0, py::arg("depth_trunc") = py::none(),
           py::arg("time") = py::none(), py::arg("name") = "",
           "Tracks a depth image whose pose is unknown against the field of the frames before and "
           "fuses it when the fit holds: {'pose': camera to world 4 x 4, 'fused', 'inliers', "
           "'rms', 'why'}; the first frame's camera is the world frame")
      .def("mesh", &meshOf,
           "Fuses every frame added: (vertices (N, 3), faces (M, 3), colours (N, 3) or None) on "
           "rank 0, empty arrays on the others")
      .def(
          "save_checkpoint",
          [](Fusion& f, const std::string& path) {
            py::gil_scoped_release free;
            f.saveCheckpoint(path);
          },
          py::arg("path"),
          "Fuses the frames and writes the field to an HDF5 checkpoint (rangefuse mesh and info "
          "read it, and Fusion.resume)")
      .def_static(
          "resume",
          [](const std::string& path, const py::object& comm) {
            const MPI_Comm c = commOf(comm);
            py::gil_scoped_release free;
            return Fusion::resume(path, c);
          },
          py::arg("path"), py::arg("comm") = py::none(),
          "A fusion holding a checkpoint's finished field (saved here or by rangefuse fuse "
          "--checkpoint): its mesh(); it takes no more frames")
      .def_property_readonly("frames", &Fusion::frames, "frames added so far");
  m.def("read_grid", &readGrid, py::arg("path"),
        "A PLY range grid (as the Stanford scans): (points (rows, cols, 3) with NaN where "
        "nothing was measured, colours (rows, cols, 3) bytes or None), as add_grid takes them");
  m.def("read_depth", &readDepth, py::arg("path"), "A 16-bit depth PNG: (height, width) uint16");
  m.def("read_colour", &readColour, py::arg("path"),
        "An 8-bit colour PNG or JPEG: (height, width, 3) bytes");
  m.def("read_frames", &readFrames, py::arg("folder"),
        "A TUM or Redwood depth folder: [(depth path, colour path or None, intrinsics 3 x 3, "
        "depth_scale, camera-to-world 4 x 4 or None without a trajectory, time)]");
  m.def("read_conf", &readConf, py::arg("path"),
        "A Stanford .conf: [(scan path, 4 x 4 pose)], paths resolved against its folder");
}
