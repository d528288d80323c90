#!/usr/bin/env python3
"""What a depth camera's frames look like, to check a synthetic sensor against a real one.

Usage: python3 jobs/sensor_statistics.py FOLDER [EVERY (10)] [FIRST] [LAST] [--json]

FOLDER is a 7-Scenes folder (frame-NNNNNN.depth.png, mm), a Redwood one (depth/*.png, mm) or a
TUM one (depth/*.png, 1/5000 m). Every EVERY-th frame from FIRST to LAST (by position) is read.
Prints, pooled over the frames:
- noise by depth: from second differences along rows and columns within a surface (neighbours
  within 5 % in depth), sigma = trimmed RMS (largest 5 % dropped) / sqrt(6), in 0.25 m bins;
- depth step: the median gap between distinct depths in each bin (disparity quantisation);
- edges: pixels whose window of 5 x 5 holds valid depths more than 10 % apart; the share of
  them without depth (holes at edges: shadows, dropped edges);
- flying pixels: the share of edge pixels whose depth lies more than 10 % from both the
  nearest and the farthest depth within one pixel (a mixed return between two surfaces).
"""
import glob
import json
import os
import sys

import numpy as np
import open3d as o3d


def frames(folder):
    """Depth image paths in order, and metres per count."""
    seven = sorted(glob.glob(os.path.join(folder, "frame-*.depth.png")))
    if seven:
        return seven, 1e-3
    images = sorted(glob.glob(os.path.join(folder, "depth", "*.png")))
    tum = os.path.exists(os.path.join(folder, "depth.txt"))
    return images, (1 / 5000 if tum else 1e-3)


def window_extremes(z, radius):
    """Per pixel, the nearest and farthest valid depth within the (2 radius + 1)^2 window."""
    big = np.where(z > 0, z, np.inf)
    small = np.where(z > 0, z, 0)
    near = np.full_like(z, np.inf)
    far = np.zeros_like(z)
    h, w = z.shape
    pb = np.pad(big, radius, constant_values=np.inf)
    ps = np.pad(small, radius, constant_values=0)
    for dy in range(2 * radius + 1):
        for dx in range(2 * radius + 1):
            near = np.minimum(near, pb[dy:dy + h, dx:dx + w])
            far = np.maximum(far, ps[dy:dy + h, dx:dx + w])
    return near, far


def statistics(paths, unit):
    bins = np.arange(0.5, 4.01, 0.25)
    second = [[] for _ in bins]
    values = [set() for _ in bins]
    pixels = holes = edge = edge_holes = flying = 0
    for path in paths:
        z = np.asarray(o3d.io.read_image(path)).astype(np.float64) * unit
        valid = z > 0
        pixels += z.size
        holes += int((~valid).sum())
        for axis in (0, 1):
            a = np.moveaxis(z, axis, 0)
            p, c, n = a[:-2], a[1:-1], a[2:]
            ok = (p > 0) & (c > 0) & (n > 0)
            ok &= (np.abs(p - c) <= 0.05 * c) & (np.abs(n - c) <= 0.05 * c)
            d = np.abs(p - 2 * c + n)[ok]
            k = np.digitize(c[ok], bins) - 1
            for b in range(len(bins)):
                second[b].append(d[k == b])
        # Near a depth edge: the valid depths within 2 pixels differ by more than 10 %.
        near, far = window_extremes(z, 2)
        beside = np.isfinite(near) & (far > 1.1 * near)
        edge += int(beside.sum())
        edge_holes += int((beside & ~valid).sum())
        # A mixed return: a depth more than 10 % from both sides of the edge (within 1 pixel).
        n1, f1 = window_extremes(z, 1)
        flying += int((beside & valid & (z > 1.1 * n1) & (z < f1 / 1.1)).sum())
        for b, lo in enumerate(bins):
            sel = z[(z >= lo) & (z < lo + 0.25)]
            if sel.size:
                values[b].update(np.unique(sel).tolist())
    noise = []
    for b, lo in enumerate(bins):
        d = np.concatenate(second[b]) if second[b] else np.array([])
        if d.size < 2000:
            continue
        d = np.sort(d)[: int(0.95 * d.size)]
        v = np.array(sorted(values[b]))
        step = float(np.median(np.diff(v))) if v.size > 2 else 0.0
        noise.append({"depth": lo + 0.125, "sigma_mm": 1000 * float(np.sqrt(np.mean(d * d) / 6)),
                      "step_mm": 1000 * step, "samples": int(d.size)})
    return {"frames": len(paths), "hole_share": holes / pixels,
            "edge_pixel_share": edge / pixels,
            "holes_at_edges": edge_holes / max(edge, 1),
            "flying_at_edges": flying / max(edge, 1), "noise": noise}


def main():
    args = [a for a in sys.argv[1:] if a != "--json"]
    paths, unit = frames(args[0])
    every = int(args[1]) if len(args) > 1 else 10
    first = int(args[2]) if len(args) > 2 else 0
    last = int(args[3]) if len(args) > 3 else len(paths)
    s = statistics(paths[first:last:every], unit)
    if "--json" in sys.argv:
        print(json.dumps(s))
        return
    print(f"{s['frames']} frames: holes {100 * s['hole_share']:.1f} %, edge pixels "
          f"{100 * s['edge_pixel_share']:.2f} %, of which holes {100 * s['holes_at_edges']:.1f} % "
          f"and flying {100 * s['flying_at_edges']:.1f} %")
    for n in s["noise"]:
        print(f"  {n['depth']:.2f} m: sigma {n['sigma_mm']:.2f} mm, step {n['step_mm']:.1f} mm")


if __name__ == "__main__":
    main()
