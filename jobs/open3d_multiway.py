#!/usr/bin/env python3
"""Open3D 0.16 multiway registration of the scans a .conf lists, for benchmarks.

Usage: python3 jobs/open3d_multiway.py IN.conf VOXEL OUT.conf

The Open3D tutorial's method: every scan downsampled to VOXEL with normals, point-to-plane ICP
over every pair of scans (coarse at 6 voxels, then fine at 1.5 voxels) started from the poses
in IN.conf, then a pose graph over all pairs that overlap (those with an ICP fitness of 0.3 or more
certain, the others prunable) optimised with the first scan fixed.
Writes the poses in the first scan's frame, the Stanford .conf way, and prints the seconds spent
reading and registering.
"""
import os
import sys
import time

import numpy as np
import open3d as o3d


def read_vertices(path):
    """x y z of the vertices of a range-grid PLY (ASCII, or binary little-endian floats)."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no end_header")
            header.append(line.decode("ascii").strip())
            if header[-1] == "end_header":
                break
        count, props, in_vertex = 0, 0, False
        for h in header:
            if h.startswith("element "):
                in_vertex = h.split()[1] == "vertex"
                if in_vertex:
                    count = int(h.split()[2])
            elif h.startswith("property") and in_vertex:
                props += 1
        if "format ascii 1.0" in header:
            rows = [f.readline().split()[:3] for _ in range(count)]
            return np.array(rows, dtype=np.float64)
        data = np.frombuffer(f.read(4 * props * count), dtype="<f4").reshape(count, props)
        return data[:, :3].astype(np.float64)


def quaternion_matrix(qx, qy, qz, qw):
    return np.array([[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
                     [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
                     [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])


def matrix_quaternion(R):
    w = np.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return x, y, z, w


def read_conf(path):
    scans = []
    for line in open(path):
        t = line.split()
        if t and t[0] == "bmesh":
            v = list(map(float, t[2:9]))
            pose = np.eye(4)
            pose[:3, :3] = quaternion_matrix(*v[3:7]).T  # Stanford keeps the conjugate
            pose[:3, 3] = v[:3]
            scans.append((t[1], pose))
    return scans


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    conf, voxel, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    scans = read_conf(conf)
    folder = os.path.dirname(os.path.abspath(conf))
    start = time.time()
    clouds = []
    for name, _ in scans:
        pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(read_vertices(os.path.join(folder, name))))
        pc = pc.voxel_down_sample(voxel)
        pc.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=3 * voxel, max_nn=30))
        clouds.append(pc)
    read_s = time.time() - start
    start = time.time()
    reg = o3d.pipelines.registration
    p2l = reg.TransformationEstimationPointToPlane()
    first = scans[0][1]
    graph = reg.PoseGraph()
    for _, pose in scans:  # node k: scan k's frame to the first scan's
        graph.nodes.append(reg.PoseGraphNode(np.linalg.inv(first) @ pose))
    for i in range(len(scans)):
        for j in range(i + 1, len(scans)):
            init = np.linalg.inv(scans[j][1]) @ scans[i][1]  # i's frame to j's
            coarse = reg.registration_icp(clouds[i], clouds[j], 6 * voxel, init, p2l)
            fine = reg.registration_icp(clouds[i], clouds[j], 1.5 * voxel, coarse.transformation, p2l)
            if fine.fitness < 0.1:
                continue
            info = reg.get_information_matrix_from_point_clouds(
                clouds[i], clouds[j], 1.5 * voxel, fine.transformation)
            # Pairs that overlap well are kept; the others may be pruned as outliers.
            graph.edges.append(reg.PoseGraphEdge(i, j, fine.transformation, info,
                                                 uncertain=fine.fitness < 0.3))
    reg.global_optimization(
        graph, reg.GlobalOptimizationLevenbergMarquardt(),
        reg.GlobalOptimizationConvergenceCriteria(),
        reg.GlobalOptimizationOption(max_correspondence_distance=1.5 * voxel,
                                     edge_prune_threshold=0.25, reference_node=0))
    register_s = time.time() - start
    with open(out, "w") as f:
        for (name, _), node in zip(scans, graph.nodes):
            pose = first @ node.pose
            x, y, z, w = matrix_quaternion(pose[:3, :3].T)
            t = pose[:3, 3]
            f.write(f"bmesh {name} {t[0]!r} {t[1]!r} {t[2]!r} {x!r} {y!r} {z!r} {w!r}\n")
    print(f"read {read_s:.2f} s, register {register_s:.2f} s, {len(graph.edges)} edges")


if __name__ == "__main__":
    main()
