#!/usr/bin/env python3
"""Open3D 0.16 ScalableTSDFVolume on a rangefuse synthetic scan set, for benchmarks.

Usage: python3 jobs/open3d_tsdf.py SET_DIR VOXEL OUT.ply [TRUNC_VOXELS]

SET_DIR is what `rangefuse scan` writes: scan.json (pinhole intrinsics and true poses) and one
range-grid PLY per view. Each view becomes a depth image (the scanner looks along -z of its
frame; Open3D along +z, so the camera frame is mirrored in z). Prints the seconds spent loading
(Python parsing, not counted as compute), converting to depth images, integrating and
extracting, and the peak resident memory of the process.
"""
import json
import os
import resource
import sys
import time

import numpy as np
import open3d as o3d


def read_vertices(path):
    """The float x y z vertices of a binary little-endian range-grid PLY."""
    with open(path, "rb") as f:
        header = b""
        while not header.endswith(b"end_header\n"):
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no end_header")
            header += line
        count = 0
        for line in header.decode("ascii").splitlines():
            if line.startswith("element vertex "):
                count = int(line.split()[2])
        return np.frombuffer(f.read(12 * count), dtype="<f4").reshape(count, 3).astype(np.float64)


def depth_image(points, view):
    """Pixels from the points' own rays (noise moves points along them), depth along the axis."""
    w, h = view["width"], view["height"]
    z = -points[:, 2]
    col = np.rint(points[:, 0] / z * view["fx"] + view["cx"]).astype(np.int64)
    row = np.rint(points[:, 1] / z * view["fy"] + view["cy"]).astype(np.int64)
    ok = (z > 0) & (col >= 0) & (col < w) & (row >= 0) & (row < h)
    depth = np.zeros((h, w), dtype=np.float32)
    depth[row[ok], col[ok]] = z[ok]
    return depth


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    set_dir, voxel, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    trunc = float(sys.argv[4]) if len(sys.argv) > 4 else 4.0
    meta = json.load(open(os.path.join(set_dir, "scan.json")))
    width, height = meta["settings"]["width"], meta["settings"]["height"]
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=voxel, sdf_trunc=trunc * voxel,
        color_type=o3d.pipelines.integration.TSDFVolumeColorType.NoColor)
    mirror = np.diag([1.0, 1.0, -1.0, 1.0])
    load = convert = integrate = 0.0
    for scan in meta["scans"]:
        t0 = time.perf_counter()
        points = read_vertices(os.path.join(set_dir, scan["name"]))
        t1 = time.perf_counter()
        view = dict(scan, width=width, height=height)
        depth = o3d.geometry.Image(depth_image(points, view))
        color = o3d.geometry.Image(np.zeros((view["height"], view["width"], 3), dtype=np.uint8))
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            color, depth, depth_scale=1.0, depth_trunc=1e9, convert_rgb_to_intensity=False)
        intr = o3d.camera.PinholeCameraIntrinsic(view["width"], view["height"], scan["fx"],
                                                 scan["fy"], scan["cx"], scan["cy"])
        pose = np.eye(4)
        pose[:3, :3] = np.array(scan["truth"]["rotation"])
        pose[:3, 3] = np.array(scan["truth"]["translation"])
        extrinsic = mirror @ np.linalg.inv(pose)  # world -> Open3D camera
        t2 = time.perf_counter()
        volume.integrate(rgbd, intr, extrinsic)
        t3 = time.perf_counter()
        load += t1 - t0
        convert += t2 - t1
        integrate += t3 - t2
    t0 = time.perf_counter()
    mesh = volume.extract_triangle_mesh()
    extract = time.perf_counter() - t0
    o3d.io.write_triangle_mesh(out, mesh)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"open3d: load {load:.2f} s (python), depth conversion {convert:.2f} s, integrate "
          f"{integrate:.2f} s, extract {extract:.2f} s, compute {convert + integrate + extract:.2f} s, "
          f"peak memory {peak:.0f} MiB, {len(mesh.triangles)} triangles")


if __name__ == "__main__":
    main()
