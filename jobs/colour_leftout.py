#!/usr/bin/env python3
"""Colour judged against frames left out of the fusion, for recordings without a true model.

Usage:
  python3 jobs/colour_leftout.py split SEQ_DIR EVERY OUT_DIR
      writes OUT_DIR, a TUM folder of SEQ_DIR's frames but every EVERY-th (frame 0, EVERY, ...),
      linking its images, poses and intrinsics
  python3 jobs/colour_leftout.py judge SEQ_DIR VOXEL EVERY MESH.ply...
      for each left-out frame of SEQ_DIR, projects each mesh's vertices into its colour image
      and compares their colour with the pixel's

SEQ_DIR is a TUM RGB-D folder (depth.txt, rgb.txt, groundtruth.txt, camera_intrinsic.json) as
`rangefuse scan --format tum --texture S` writes it, or a real recording in that layout. A vertex
counts for a frame when it projects inside the image in front of the camera and the frame's
depth there agrees with its own to within 3 voxels plus the sensor's depth-squared noise
(0.005 z^2): the frame saw it. Its error is the mean over the channels of |vertex colour - pixel
colour|, in steps of 1/255. "At image edges" are the pixels where the colour image's grey level
spans 32 levels or more over their 3 x 3 neighbourhood: where colour changes, and where fusion
blurs it.
"""
import json
import os
import sys

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from open3d_sequence import data_lines, tum_colours, tum_frames  # noqa: E402

EDGE_RANGE = 32  # grey levels over a 3 x 3 neighbourhood that make a pixel an image edge


def left_out(k, every):
    return k % every == 0


def split(seq, every, out):
    os.makedirs(out, exist_ok=True)
    for name in ("depth", "rgb", "groundtruth.txt", "camera_intrinsic.json"):
        target = os.path.join(out, name)
        if not os.path.exists(target):
            os.symlink(os.path.abspath(os.path.join(seq, name)), target)
    depth = data_lines(f"{seq}/depth.txt")
    kept = [t for k, t in enumerate(float(l[0]) for l in depth) if not left_out(k, every)]
    with open(f"{out}/depth.txt", "w") as f:
        for k, l in enumerate(depth):
            if not left_out(k, every):
                f.write(" ".join(l) + "\n")
    # Every colour image stays listed: fusion takes the one nearest each kept depth frame.
    with open(f"{out}/rgb.txt", "w") as f:
        for l in data_lines(f"{seq}/rgb.txt"):
            f.write(" ".join(l) + "\n")
    print(f"split: {len(kept)} frames fused, {len(depth) - len(kept)} left out -> {out}")


def image_edges(colour):
    grey = colour.astype(np.float32).mean(axis=2)
    pad = np.pad(grey, 1, mode="edge")
    h, w = grey.shape
    shifted = [pad[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)]
    return (np.max(shifted, axis=0) - np.min(shifted, axis=0)) >= EDGE_RANGE


def frame_errors(vertices, colours, depth, colour, pose, k, voxel, depth_scale):
    """(errors, at_edge) for the vertices the frame saw."""
    h, w = depth.shape
    cam = (vertices - pose[:3, 3]) @ pose[:3, :3]
    z = cam[:, 2]
    front = z > 1e-6
    u = np.full(len(z), -1)
    v = np.full(len(z), -1)
    u[front] = np.rint(k[0] * cam[front, 0] / z[front] + k[6]).astype(int)
    v[front] = np.rint(k[4] * cam[front, 1] / z[front] + k[7]).astype(int)
    inside = front & (u >= 0) & (u < w) & (v >= 0) & (v < h)
    idx = np.nonzero(inside)[0]
    d = depth[v[idx], u[idx]] / depth_scale
    seen = (d > 0) & (np.abs(z[idx] - d) <= 3 * voxel + 0.005 * z[idx] ** 2)
    idx = idx[seen]
    pixel = colour[v[idx], u[idx]].astype(np.float64)
    errors = np.abs(255.0 * colours[idx] - pixel).mean(axis=1)
    return errors, image_edges(colour)[v[idx], u[idx]]


def judge(seq, voxel, every, meshes):
    frames, depth_scale = tum_frames(seq)
    colour_paths = tum_colours(seq, [t for _, _, t in frames])
    cam = json.load(open(f"{seq}/camera_intrinsic.json"))
    k = cam["intrinsic_matrix"]
    loaded = []
    for path in meshes:
        m = o3d.io.read_triangle_mesh(path)
        if not m.has_vertex_colors():
            sys.exit(f"colour_leftout: {path} has no vertex colours")
        loaded.append((path, np.asarray(m.vertices), np.asarray(m.vertex_colors)))
    totals = {path: ([], []) for path in meshes}
    judged = 0
    for index, ((depth_path, pose, _), colour_path) in enumerate(zip(frames, colour_paths)):
        if not left_out(index, every) or colour_path is None:
            continue
        judged += 1
        depth = np.asarray(o3d.io.read_image(depth_path)).astype(np.float64)
        colour = np.asarray(o3d.io.read_image(colour_path))[:, :, :3]
        for path, vertices, colours in loaded:
            errors, edges = frame_errors(vertices, colours, depth, colour, pose, k, voxel,
                                         depth_scale)
            totals[path][0].append(errors)
            totals[path][1].append(edges)
    print(f"{judged} frames left out of the fusion judge the colour")
    print("| mesh | vertex views judged | mean error (of 255) | at image edges | elsewhere |")
    print("|---|---|---|---|---|")
    for path in meshes:
        errors = np.concatenate(totals[path][0])
        edges = np.concatenate(totals[path][1])
        print(f"| {path} | {len(errors)} | {errors.mean():.2f} | {errors[edges].mean():.2f} | "
              f"{errors[~edges].mean():.2f} |")


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    if sys.argv[1] == "split":
        split(sys.argv[2], int(sys.argv[3]), sys.argv[4])
    elif sys.argv[1] == "judge" and len(sys.argv) > 5:
        judge(sys.argv[2], float(sys.argv[3]), int(sys.argv[4]), sys.argv[5:])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
