#!/usr/bin/env python3
"""Open3D 0.16 ScalableTSDFVolume on a rangefuse scan set, for benchmarks.

Usage: python3 jobs/open3d_tsdf.py SET VOXEL OUT.ply [TRUNC_VOXELS]

SET is what `rangefuse scan` writes (a folder: scan.json with pinhole intrinsics and true
poses, and one range-grid PLY per view), or a Stanford .conf of near-orthographic range grids
(Cyberware, as the real bunny's): those have no pinhole, so each is seen by a pinhole placed far
along the scanner's +z (its rays then nearly parallel, 20 object sizes away) whose pixel is the
grid's median sample step at the object. Each view becomes a depth image (the scanner looks
along -z of its frame; Open3D along +z, so the camera frame is mirrored in z). Prints the seconds
spent loading (Python parsing, not counted as compute), converting to depth images, integrating
and extracting, and the peak resident memory of the process.
"""
import json
import os
import resource
import sys
import time

import numpy as np
import open3d as o3d


def read_vertices(path):
    """The x y z vertices of a range-grid PLY: binary little-endian floats, or ASCII."""
    with open(path, "rb") as f:
        header = b""
        while not header.endswith(b"end_header\n"):
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no end_header")
            header += line
        count, ascii_format = 0, False
        for line in header.decode("ascii").splitlines():
            if line.startswith("element vertex "):
                count = int(line.split()[2])
            if line.startswith("format ascii"):
                ascii_format = True
        if ascii_format:
            return np.loadtxt(f, max_rows=count, usecols=(0, 1, 2), ndmin=2)
        return np.frombuffer(f.read(12 * count), dtype="<f4").reshape(count, 3).astype(np.float64)


def synthetic_views(set_dir):
    """Views of a `rangefuse scan` folder: (points in the camera frame, intrinsics, pose)."""
    meta = json.load(open(os.path.join(set_dir, "scan.json")))
    width, height = meta["settings"]["width"], meta["settings"]["height"]
    for scan in meta["scans"]:
        pose = np.eye(4)
        pose[:3, :3] = np.array(scan["truth"]["rotation"])
        pose[:3, 3] = np.array(scan["truth"]["translation"])
        view = dict(width=width, height=height, fx=scan["fx"], fy=scan["fy"], cx=scan["cx"],
                    cy=scan["cy"])
        yield read_vertices(os.path.join(set_dir, scan["name"])), view, pose


def far_pinhole(points):
    """A pinhole on the grid's +z side, 20 object sizes away, with a pixel of the grid's step:
    its centre in the scan's frame, and its intrinsics."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    step = np.median(np.linalg.norm(np.diff(points, axis=0), axis=1))
    distance = 20 * np.linalg.norm(hi - lo)
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + distance])
    width, height = (int(np.ceil((hi[a] - lo[a]) / step)) + 4 for a in (0, 1))
    view = dict(width=width, height=height, fx=distance / step, fy=distance / step,
                cx=width / 2, cy=height / 2, shared=True)
    return centre, view


def conf_views(conf):
    """Views of a Stanford .conf ('bmesh FILE tx ty tz qx qy qz qw', whose quaternion is the
    conjugate of the scan-to-world rotation, as rangefuse's reader takes it)."""
    folder = os.path.dirname(conf)
    for line in open(conf):
        words = line.split()
        if not words or words[0] != "bmesh":
            continue
        t = np.array([float(v) for v in words[2:5]])
        qx, qy, qz, qw = (float(v) for v in words[5:9])
        rotation = o3d.geometry.get_rotation_matrix_from_quaternion([qw, qx, qy, qz]).T
        points = read_vertices(os.path.join(folder, words[1]))
        centre, view = far_pinhole(points)
        pose = np.eye(4)  # camera to world: the camera's offset, then the scan's pose
        pose[:3, :3] = rotation
        pose[:3, 3] = rotation @ centre + t
        yield points - centre, view, pose


def depth_image(points, view):
    """Pixels from the points' own rays (noise moves points along them), depth along the axis;
    where points may share a pixel (view["shared"]: a far pinhole's), the nearest."""
    w, h = view["width"], view["height"]
    z = -points[:, 2]
    col = np.rint(points[:, 0] / z * view["fx"] + view["cx"]).astype(np.int64)
    row = np.rint(points[:, 1] / z * view["fy"] + view["cy"]).astype(np.int64)
    ok = (z > 0) & (col >= 0) & (col < w) & (row >= 0) & (row < h)
    row, col, z = row[ok], col[ok], z[ok]
    if view.get("shared"):
        order = np.argsort(-z)  # the nearest is written last
        row, col, z = row[order], col[order], z[order]
    depth = np.zeros((h, w), dtype=np.float32)
    depth[row, col] = z
    return depth


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    set_path, voxel, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    trunc = float(sys.argv[4]) if len(sys.argv) > 4 else 4.0
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=voxel, sdf_trunc=trunc * voxel,
        color_type=o3d.pipelines.integration.TSDFVolumeColorType.NoColor)
    mirror = np.diag([1.0, 1.0, -1.0, 1.0])
    views = conf_views(set_path) if set_path.endswith(".conf") else synthetic_views(set_path)
    load = convert = integrate = 0.0
    t0 = time.perf_counter()
    for points, view, pose in views:  # each view loaded as it is asked for
        t1 = time.perf_counter()
        depth = o3d.geometry.Image(depth_image(points, view))
        color = o3d.geometry.Image(np.zeros((view["height"], view["width"], 3), dtype=np.uint8))
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            color, depth, depth_scale=1.0, depth_trunc=1e9, convert_rgb_to_intensity=False)
        intr = o3d.camera.PinholeCameraIntrinsic(view["width"], view["height"], view["fx"],
                                                 view["fy"], view["cx"], view["cy"])
        extrinsic = mirror @ np.linalg.inv(pose)  # world -> Open3D camera
        t2 = time.perf_counter()
        volume.integrate(rgbd, intr, extrinsic)
        t3 = time.perf_counter()
        load += t1 - t0
        convert += t2 - t1
        integrate += t3 - t2
        t0 = time.perf_counter()
    t0 = time.perf_counter()
    mesh = volume.extract_triangle_mesh()
    extract = time.perf_counter() - t0
    o3d.io.write_triangle_mesh(out, mesh)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"open3d: load {load:.3f} s (python), depth conversion {convert:.3f} s, integrate "
          f"{integrate:.3f} s, extract {extract:.3f} s, compute {convert + integrate + extract:.3f} s, "
          f"peak memory {peak:.0f} MiB, {len(mesh.triangles)} triangles")


if __name__ == "__main__":
    main()
