#!/usr/bin/env python3
"""Open3D 0.16 screened Poisson reconstruction of a rangefuse scan set, for the hole-filling
benchmark: every scan's points in the world, normals estimated from 30 neighbours and turned
toward the scan's sensor, `create_from_point_cloud_poisson` at the given depth, then the
vertices whose density is in the lowest TRIM quantile removed (0: untrimmed, the closed surface).

Usage: python3 jobs/open3d_poisson.py SET OUT.ply [DEPTH] [TRIM]
SET as for open3d_tsdf.py: a `rangefuse scan` folder or a Stanford .conf. Prints the seconds.
"""
import os
import sys
import time

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from open3d_tsdf import conf_views, synthetic_views  # noqa: E402


def world_points(set_path):
    """All points in the world frame, each with its sensor's position."""
    views = conf_views(set_path) if set_path.endswith(".conf") else synthetic_views(set_path)
    points, sensors = [], []
    for p, _, pose in views:
        world = p @ pose[:3, :3].T + pose[:3, 3]
        points.append(world)
        sensors.append(np.repeat(pose[:3, 3][None, :], len(world), axis=0))
    return np.concatenate(points), np.concatenate(sensors)


def main():
    set_path, out = sys.argv[1], sys.argv[2]
    depth = int(sys.argv[3]) if len(sys.argv) > 3 else 9
    trim = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
    points, sensors = world_points(set_path)
    start = time.time()
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(30))
    normals = np.asarray(cloud.normals)
    flip = np.sum(normals * (sensors - points), axis=1) < 0
    normals[flip] *= -1
    cloud.normals = o3d.utility.Vector3dVector(normals)
    mesh, density = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=depth)
    if trim > 0:
        density = np.asarray(density)
        mesh.remove_vertices_by_mask(density < np.quantile(density, trim))
    seconds = time.time() - start
    o3d.io.write_triangle_mesh(out, mesh)
    print(f"poisson depth {depth} trim {trim}: {len(mesh.triangles)} triangles, {seconds:.2f} s")


if __name__ == "__main__":
    main()
