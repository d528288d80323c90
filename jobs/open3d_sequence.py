#!/usr/bin/env python3
"""Open3D 0.16 ScalableTSDFVolume on a depth-image sequence folder, for benchmarks.

Usage: python3 jobs/open3d_sequence.py SEQ_DIR VOXEL OUT.ply [TRUNC_VOXELS] [rgb]

SEQ_DIR is a TUM RGB-D folder (depth.txt, groundtruth.txt matched by nearest timestamp within
20 ms, depth in 1/5000 m) or a Redwood one (depth/*.png in name order, trajectory.log, depth in
mm), with camera_intrinsic.json, as `rangefuse scan --format tum|redwood` writes them. Open3D
decodes the PNG files itself (o3d.io.read_image), so reading counts as compute here, as it does
for rangefuse. Prints the seconds spent reading, integrating and extracting, and the peak
resident memory of the process. With `rgb` the volume is RGB8 and each frame's colour image
(TUM rgb.txt by nearest timestamp within 20 ms, Redwood color/ in name order) is integrated
with it, so the mesh has vertex colours.
"""
import bisect
import json
import os
import resource
import sys
import time

import numpy as np
import open3d as o3d


def quaternion_matrix(qx, qy, qz, qw):
    n = np.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    x, y, z, w = qx / n, qy / n, qz / n, qw / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def data_lines(path):
    with open(path) as f:
        return [l.split() for l in f if l.strip() and not l.lstrip().startswith("#")]


def nearest(times, t):
    k = bisect.bisect_left(times, t)
    return min((j for j in (k - 1, k) if 0 <= j < len(times)), key=lambda j: abs(times[j] - t))


def tum_colours(seq, depth_times):
    """The colour image nearest in time to each depth frame (within 20 ms), or None."""
    rows = [(float(l[0]), l[1]) for l in data_lines(f"{seq}/rgb.txt")]
    times = [t for t, _ in rows]
    out = []
    for t in depth_times:
        best = nearest(times, t)
        out.append(os.path.join(seq, rows[best][1]) if abs(times[best] - t) <= 0.02 else None)
    return out


def tum_frames(seq):
    """(depth image path, camera-to-world 4x4, time) for frames with a pose within 20 ms."""
    poses = [(float(l[0]), [float(v) for v in l[1:8]]) for l in data_lines(f"{seq}/groundtruth.txt")]
    times = [t for t, _ in poses]
    frames = []
    for l in data_lines(f"{seq}/depth.txt"):
        t = float(l[0])
        best = nearest(times, t)
        if abs(times[best] - t) > 0.02:
            continue
        v = poses[best][1]
        m = np.eye(4)
        m[:3, :3] = quaternion_matrix(*v[3:7])
        m[:3, 3] = v[:3]
        frames.append((os.path.join(seq, l[1]), m, t))
    return frames, 5000.0


def redwood_frames(seq):
    rows = data_lines(f"{seq}/trajectory.log")
    poses = [np.array(rows[k + 1:k + 5], dtype=float) for k in range(0, len(rows), 5)]
    images = sorted(f for f in os.listdir(f"{seq}/depth") if f.endswith(".png"))
    return [(f"{seq}/depth/{f}", m, k) for k, (f, m) in enumerate(zip(images, poses))], 1000.0


def colour_paths(seq, frames, tum):
    if tum:
        return tum_colours(seq, [t for _, _, t in frames])
    folder = f"{seq}/color"
    images = sorted(f for f in os.listdir(folder) if f.endswith((".png", ".jpg")))
    return [f"{folder}/{f}" for f in images]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    seq, voxel, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    trunc = float(sys.argv[4]) if len(sys.argv) > 4 else 4.0
    rgb = len(sys.argv) > 5 and sys.argv[5] == "rgb"
    tum = os.path.exists(f"{seq}/depth.txt")
    frames, scale = tum_frames(seq) if tum else redwood_frames(seq)
    colours = colour_paths(seq, frames, tum) if rgb else [None] * len(frames)
    cam = json.load(open(f"{seq}/camera_intrinsic.json"))
    k = cam["intrinsic_matrix"]
    intrinsic = o3d.camera.PinholeCameraIntrinsic(cam["width"], cam["height"], k[0], k[4], k[6],
                                                  k[7])
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=voxel, sdf_trunc=trunc * voxel,
        color_type=o3d.pipelines.integration.TSDFVolumeColorType.RGB8 if rgb else
        o3d.pipelines.integration.TSDFVolumeColorType.NoColor)
    grey = o3d.geometry.Image(np.zeros((cam["height"], cam["width"], 3), dtype=np.uint8))
    read = integrate = 0.0
    for (path, pose, _), colour_path in zip(frames, colours):
        t0 = time.perf_counter()
        depth = o3d.io.read_image(path)
        colour = o3d.io.read_image(colour_path) if colour_path else grey
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            colour, depth, depth_scale=scale, depth_trunc=1e9, convert_rgb_to_intensity=False)
        t1 = time.perf_counter()
        volume.integrate(rgbd, intrinsic, np.linalg.inv(pose))
        t2 = time.perf_counter()
        read += t1 - t0
        integrate += t2 - t1
    t0 = time.perf_counter()
    mesh = volume.extract_triangle_mesh()
    extract = time.perf_counter() - t0
    o3d.io.write_triangle_mesh(out, mesh)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"open3d: {len(frames)} frames, read {read:.2f} s, integrate {integrate:.2f} s, "
          f"extract {extract:.2f} s, total {read + integrate + extract:.2f} s, "
          f"peak memory {peak:.0f} MiB, {len(mesh.triangles)} triangles")


if __name__ == "__main__":
    main()
