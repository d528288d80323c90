#!/usr/bin/env python3
"""Open3D 0.16 frame-to-frame ICP on a depth-image sequence without its poses, then
ScalableTSDFVolume at the poses found: the usual recipe without colour, for benchmarks.

Usage: python3 jobs/open3d_track.py SEQ_DIR VOXEL OUT.ply TRAJECTORY.txt [FIRST_POSE]

SEQ_DIR is a TUM folder (depth.txt, depth in 1/5000 m) or a Redwood / recorder one (depth/*.png
in name order, depth in mm), with camera_intrinsic.json; any trajectory in it is ignored. Each
frame is registered to the previous one by point-to-plane ICP on down-sampled point clouds,
coarse to fine (4, 2 and 1 voxels; correspondences within 2 of the level's voxels), started
from the previous frame's motion. Writes the trajectory in TUM format (camera to world, the
first camera at the identity or at FIRST_POSE 'tx,ty,tz,qx,qy,qz,qw') and prints the seconds
spent tracking and fusing.
"""
import json
import os
import resource
import sys
import time

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.dirname(__file__))
from open3d_sequence import data_lines  # noqa: E402


def frames_of(seq):
    """(time, depth image path) in order, and the depth scale (counts a metre)."""
    if os.path.exists(f"{seq}/depth.txt"):
        return [(float(l[0]), os.path.join(seq, l[1])) for l in data_lines(f"{seq}/depth.txt")], 5000.0
    images = sorted(f for f in os.listdir(f"{seq}/depth") if f.endswith(".png"))
    return [(k / 30.0, f"{seq}/depth/{f}") for k, f in enumerate(images)], 1000.0


def quaternion(m):
    """(qx, qy, qz, qw) of a rotation matrix."""
    w = np.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + m[0, 0] - m[1, 1] - m[2, 2])) / 2, m[2, 1] - m[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - m[0, 0] + m[1, 1] - m[2, 2])) / 2, m[0, 2] - m[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - m[0, 0] - m[1, 1] + m[2, 2])) / 2, m[1, 0] - m[0, 1])
    return x, y, z, w


def pyramid(cloud, voxel):
    levels = []
    for factor in (4, 2, 1):
        down = cloud.voxel_down_sample(voxel * factor)
        down.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=4 * voxel * factor,
                                                                   max_nn=30))
        levels.append((down, voxel * factor))
    return levels


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    seq, voxel, out, trajectory = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
    frames, scale = frames_of(seq)
    first = np.eye(4)
    if len(sys.argv) > 5:
        v = [float(x) for x in sys.argv[5].split(",")]
        x, y, z, w = v[3:7]
        first[:3, :3] = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        first[:3, 3] = v[:3]
    cam = json.load(open(f"{seq}/camera_intrinsic.json"))
    k = cam["intrinsic_matrix"]
    intrinsic = o3d.camera.PinholeCameraIntrinsic(cam["width"], cam["height"], k[0], k[4], k[6],
                                                  k[7])
    estimation = o3d.pipelines.registration.TransformationEstimationPointToPlane()
    t0 = time.perf_counter()
    poses, previous, motion = [], None, np.eye(4)
    depths = []
    for t, path in frames:
        depth = o3d.io.read_image(path)
        depths.append(depth)
        cloud = o3d.geometry.PointCloud.create_from_depth_image(depth, intrinsic,
                                                                depth_scale=scale, depth_trunc=1e9)
        levels = pyramid(cloud, voxel)
        if previous is None:
            poses.append(first)
        else:
            step = motion
            for (source, v), (target, _) in zip(levels, previous):
                step = o3d.pipelines.registration.registration_icp(
                    source, target, 2 * v, step, estimation,
                    o3d.pipelines.registration.ICPConvergenceCriteria(max_iteration=30)).transformation
            motion = step
            poses.append(poses[-1] @ step)
        previous = levels
    track = time.perf_counter() - t0
    t0 = time.perf_counter()
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=voxel, sdf_trunc=4 * voxel,
        color_type=o3d.pipelines.integration.TSDFVolumeColorType.NoColor)
    colour = o3d.geometry.Image(np.zeros((cam["height"], cam["width"], 3), dtype=np.uint8))
    for depth, pose in zip(depths, poses):
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            colour, depth, depth_scale=scale, depth_trunc=1e9, convert_rgb_to_intensity=False)
        volume.integrate(rgbd, intrinsic, np.linalg.inv(pose))
    mesh = volume.extract_triangle_mesh()
    fuse = time.perf_counter() - t0
    o3d.io.write_triangle_mesh(out, mesh)
    with open(trajectory, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for (t, _), m in zip(frames, poses):
            f.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % ((t,) + tuple(m[:3, 3]) +
                                                                 quaternion(m[:3, :3])))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    n = len(frames)
    print(f"open3d-icp: {n} frames, track {track:.2f} s ({n / track:.1f} frames/s), fuse "
          f"{fuse:.2f} s, total {track + fuse:.2f} s, peak memory {peak:.0f} MiB")


if __name__ == "__main__":
    main()
