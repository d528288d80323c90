#!/usr/bin/env python3
"""How well a mesh fused from some depth frames predicts frames it was not given.

Real recordings have no true surface: the frames left out of the fusion are the judge. Each
judged frame's pixels are placed in the world by its pose; a pixel's error is its distance to
the mesh (the nearest of dense area-weighted samples of it, so distances carry about half the
samples' spacing, the same for every mesh). Pixels farther than --reach from the mesh are
surface the fused frames did not see, and are counted apart.

Usage: heldout_depth.py MESH FOLDER FRAMES [--step S] [--reach M] [--samples N]
  FOLDER: a Redwood folder (depth/NNNNNN.png, camera_intrinsic.json, trajectory.log),
  FRAMES: comma-separated frame numbers to judge.
Prints one line: median, mean and share within 1 cm of the pixels within reach, and the share
of pixels within reach.
"""
import argparse
import json

import numpy as np
import open3d as o3d


def poses(path):
    rows = [l.split() for l in open(path) if l.strip()]
    out = {}
    for k in range(0, len(rows), 5):
        out[int(rows[k][0])] = np.array(rows[k + 1:k + 5], dtype=float)
    return out


def frame_points(folder, frame, pose, k, step, scale):
    depth = np.asarray(o3d.io.read_image("%s/depth/%06d.png" % (folder, frame)), dtype=float)
    depth = depth[::step, ::step] / scale
    v, u = np.nonzero(depth > 0)
    z = depth[v, u]
    u, v = u * step, v * step
    cam = np.stack([(u - k[0, 2]) * z / k[0, 0], (v - k[1, 2]) * z / k[1, 1], z, np.ones_like(z)])
    return (pose @ cam)[:3].T


def main():
    a = argparse.ArgumentParser()
    a.add_argument("mesh")
    a.add_argument("folder")
    a.add_argument("frames")
    a.add_argument("--step", type=int, default=4)
    a.add_argument("--reach", type=float, default=0.05)
    a.add_argument("--samples", type=int, default=4000000)
    a.add_argument("--scale", type=float, default=1000.0)
    o = a.parse_args()
    intr = json.load(open(o.folder + "/camera_intrinsic.json"))["intrinsic_matrix"]
    k = np.array(intr, dtype=float).reshape(3, 3).T
    traj = poses(o.folder + "/trajectory.log")
    frames = [int(x) for x in o.frames.split(",")]
    mesh = o3d.io.read_triangle_mesh(o.mesh)
    if hasattr(o3d.utility, "random"):
        o3d.utility.random.seed(7)
    cloud = mesh.sample_points_uniformly(number_of_points=o.samples)
    cloud.points.extend(mesh.vertices)
    errors = []
    for f in frames:
        pts = frame_points(o.folder, f, traj[f], k, o.step, o.scale)
        pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(pts))
        errors.append(np.asarray(pc.compute_point_cloud_distance(cloud)))
    e = np.concatenate(errors)
    near = e[e <= o.reach]
    print("median %.2f mm | mean %.2f mm | within 1 cm %.4f | within reach %.4f | pixels %d" %
          (1e3 * np.median(near), 1e3 * near.mean(), np.mean(near <= 0.01), near.size / e.size,
           e.size))


if __name__ == "__main__":
    main()
