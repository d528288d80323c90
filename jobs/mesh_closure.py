#!/usr/bin/env python3
"""Closure and invented surface of a mesh, for the hole-filling benchmark.

Usage: python3 jobs/mesh_closure.py MESH.ply SET VOXEL
Prints: faces, edges not shared by exactly two faces (0: closed 2-manifold), the area, and the
share of the area farther than 3 voxels from every input point (surface no scan saw: invented),
and for a rangefuse mesh with --fill-holes the share of the area its `filled` vertices mark.
"""
import os
import sys

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from open3d_poisson import world_points  # noqa: E402


def filled_flags(path, count):
    """The PLY's `filled` vertex property (binary little-endian, as rangefuse writes), or None."""
    with open(path, "rb") as f:
        header = b""
        while not header.endswith(b"end_header\n"):
            header += f.readline()
        props, in_vertex = [], False
        for line in header.decode("ascii").splitlines():
            if line.startswith("element"):
                in_vertex = line.startswith("element vertex")
            elif in_vertex and line.startswith("property"):
                kind, name = line.split()[1:3]
                props.append((name, {"float": "<f4", "double": "<f8", "uchar": "u1"}[kind]))
        if "filled" not in [p[0] for p in props]:
            return None
        return np.frombuffer(f.read(count * np.dtype(props).itemsize), dtype=np.dtype(props))["filled"]


def main():
    path, set_path, voxel = sys.argv[1], sys.argv[2], float(sys.argv[3])
    mesh = o3d.io.read_triangle_mesh(path)
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.triangles)
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    _, uses = np.unique(edges, axis=0, return_counts=True)
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
    # Distance of each face's centroid to the nearest input point.
    points, _ = world_points(set_path)
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    centres = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(v[f].mean(axis=1)))
    far = np.asarray(centres.compute_point_cloud_distance(cloud)) > 3 * voxel
    line = (f"faces {len(f)} open_edges {int(np.sum(uses != 2))} area {area.sum():.6g} "
            f"invented {100 * area[far].sum() / area.sum():.2f}%")
    flags = filled_flags(path, len(v))
    if flags is not None:
        marked = flags[f].any(axis=1)
        line += f" marked_filled {100 * area[marked].sum() / area.sum():.2f}%"
    print(line)


if __name__ == "__main__":
    main()
