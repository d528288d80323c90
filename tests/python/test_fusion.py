"""The Python module against the command and against known answers (run by ctest's python_tests
with PYTHONPATH at the built module, RANGEFUSE_BIN at the command, RANGEFUSE_TEST_DATA at
tests/data)."""
import os
import subprocess
import sys

import numpy as np
import pytest

import rangefuse

BIN = os.environ.get("RANGEFUSE_BIN", "rangefuse")
DATA = os.environ.get("RANGEFUSE_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))
BUNNY = os.path.join(DATA, "bunny", "bun.conf")
VOXEL = 0.002  # 2 mm: the bunny in a second


PLY_TYPES = {"float": "<f4", "double": "<f8", "uchar": "u1", "int": "<i4", "uint": "<u4"}


def read_ply(path):
    """Vertices (float32) and faces of a binary PLY as the command writes it."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line.split())
            if line == "end_header":
                break
        body = f.read()
    counts = {w[1]: int(w[2]) for w in header if w[0] == "element"}
    faces_at = next(i for i, w in enumerate(header) if w[:2] == ["element", "face"])
    vertex = np.dtype([(w[2], PLY_TYPES[w[1]]) for w in header[:faces_at] if w[0] == "property"])
    v = np.frombuffer(body, vertex, counts["vertex"])
    faces = np.frombuffer(body, np.dtype([("n", "u1"), ("i", "<i4", 3)]), counts["face"],
                          counts["vertex"] * vertex.itemsize)
    assert (faces["n"] == 3).all()
    return np.stack([v["x"], v["y"], v["z"]], 1), faces["i"]


def fuse_bunny(comm=None):
    fusion = rangefuse.Fusion(voxel=VOXEL, comm=comm)
    for path, pose in rangefuse.read_conf(BUNNY):
        points, colours = rangefuse.read_grid(path)
        fusion.add_grid(points, pose, colours=colours, name=os.path.basename(path))
    assert fusion.frames == 10
    return fusion.mesh()


def fuse_bunny_by_its_list(comm=None):
    """The bunny's scans added by their list: each file read by the rank whose share it is."""
    fusion = rangefuse.Fusion(voxel=VOXEL, comm=comm)
    fusion.add_scans(BUNNY)
    assert fusion.frames == 10
    return fusion.mesh()


def test_bunny_gives_the_commands_mesh(tmp_path):
    out = tmp_path / "bunny.ply"
    subprocess.run([BIN, "fuse", "--scans", BUNNY, "--voxel", str(VOXEL), "--out", str(out),
                    "--quiet"], check=True)
    vertices, faces, colours = fuse_bunny()
    ply_vertices, ply_faces = read_ply(out)
    assert len(faces) > 10000 and colours is None
    assert vertices.dtype == np.float64 and vertices.shape == (len(ply_vertices), 3)
    assert np.array_equal(faces, ply_faces)
    assert np.array_equal(vertices.astype(np.float32), ply_vertices)
    listed_vertices, listed_faces, _ = fuse_bunny_by_its_list()
    assert np.array_equal(listed_faces, faces)
    assert np.array_equal(listed_vertices, vertices)


def sphere_depth(K, pose, size, radius):
    """Depths (metres) of a sphere at the origin seen by a camera at pose (OpenCV axes)."""
    u, v = np.meshgrid(np.arange(size), np.arange(size))
    rays = np.stack([(u - K[0, 2]) / K[0, 0], (v - K[1, 2]) / K[1, 1], np.ones_like(u, float)], -1)
    d = rays @ pose[:3, :3].T
    eye = pose[:3, 3]
    a, b, c = (d * d).sum(-1), 2 * d @ eye, eye @ eye - radius**2
    disc = b * b - 4 * a * c
    s = (-b - np.sqrt(np.maximum(disc, 0))) / (2 * a)
    return np.where(disc > 0, s, 0.0)


def looking_at_origin(eye):
    z = -eye / np.linalg.norm(eye)
    up = np.array([1.0, 0, 0]) if abs(z[1]) > 0.9 else np.array([0, 1.0, 0])
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    pose = np.eye(4)
    pose[:3, :3] = np.stack([x, np.cross(z, x), z], 1)
    pose[:3, 3] = eye
    return pose


def test_depth_images_of_a_sphere_give_the_sphere_and_its_colour():
    K = np.array([[150.0, 0, 59.5], [0, 150, 59.5], [0, 0, 1]])
    fusion = rangefuse.Fusion(voxel=0.01, method="robust")
    colour = np.zeros((120, 120, 3), np.uint8)
    colour[:] = (30, 120, 240)
    for eye in np.vstack([np.eye(3), -np.eye(3)]) * 2.0:
        pose = looking_at_origin(eye)
        fusion.add_depth(sphere_depth(K, pose, 120, 0.5), K, pose, colour=colour)
    vertices, faces, colours = fusion.mesh()
    radii = np.linalg.norm(vertices, axis=1)
    assert len(faces) > 1000
    assert np.abs(radii - 0.5).max() < 0.01  # within a voxel everywhere
    assert np.abs(colours * 255 - (30, 120, 240)).max() < 2


@pytest.mark.parametrize("call, message", [
    (lambda f: f.add_grid(np.zeros((4, 4)), np.eye(4)), "points must be (rows, cols, 3), not shape (4, 4)"),
    (lambda f: f.add_grid(np.zeros((4, 4, 3)), np.diag([1, 1, 1, 1.0]) + np.diag([np.nan], 3)),
     "the pose is not finite"),
    (lambda f: f.add_depth(np.zeros((4, 4), np.uint16), np.eye(3), np.eye(4)[:3]),
     "a pose must be a 4 x 4 matrix, not shape (3, 4)"),
    (lambda f: f.add_depth(np.full((4, 4), -1.0), np.eye(3), np.eye(4)),
     "depth -1.000000 m (float64) is not a distance"),
    (lambda f: f.add_depth(np.full((4, 4), 70000, np.int32), np.eye(3), np.eye(4)),
     "depth count 70000 (int32) is outside a depth image's 0 to 65535"),
    (lambda f: f.add_depth(np.full((4, 4), 3.0), np.eye(3), np.eye(4), depth_scale=1e5),
     "beyond the 0.655350 m that depth_scale 100000.000000 counts a metre can hold"),
    (lambda f: f.add_depth(np.ones((4, 4), bool), np.eye(3), np.eye(4)),
     "depth of dtype bool is neither counts"),
    (lambda f: f.add_depth(np.ones((4, 4), np.complex64), np.eye(3), np.eye(4)),
     "depth of dtype complex64 is neither counts"),
    (lambda f: f.add_depth(np.zeros((4, 4), np.uint16), np.eye(3), np.diag([1, 1, -1, 1.0])),
     "the pose's rotation is a reflection"),
    (lambda f: f.mesh(), "Fusion: no frames to fuse"),
])
def test_bad_input_raises_the_commands_message(call, message):
    fusion = rangefuse.Fusion(voxel=0.01)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        call(fusion)
    assert fusion.frames == 0


def test_every_integer_dtype_is_counts_and_every_float_dtype_metres():
    # One set of depths handed over in each dtype: counts (integers, depth_scale a metre) or
    # metres (floats) give the same frames, so the same mesh bytes.
    K = np.array([[60.0, 0, 29.5], [0, 60, 29.5], [0, 0, 1]])
    views = [looking_at_origin(eye) for eye in np.vstack([np.eye(3), -np.eye(3)]) * 1.5]
    counts = [np.round(sphere_depth(K, pose, 60, 0.5) * 100) for pose in views]

    def mesh_of(dtype, metres):
        fusion = rangefuse.Fusion(voxel=0.02)
        for pose, c in zip(views, counts):
            depth = (c / 100 if metres else c).astype(dtype)
            fusion.add_depth(depth, K, pose, depth_scale=100.0)
        return fusion.mesh()

    reference = mesh_of(np.uint16, False)
    assert len(reference[1]) > 100
    for dtype in (np.uint8, np.int16, np.int32, np.uint32, np.int64):
        vertices, faces, _ = mesh_of(dtype, False)
        assert np.array_equal(vertices, reference[0]) and np.array_equal(faces, reference[1]), dtype
    for dtype in (np.float16, np.float32, np.float64):
        vertices, faces, _ = mesh_of(dtype, True)
        assert np.array_equal(vertices, reference[0]) and np.array_equal(faces, reference[1]), dtype


def test_a_checkpoint_into_a_missing_folder_is_one_line(tmp_path, capfd):
    fusion = rangefuse.Fusion(voxel=0.01)
    fusion.add_depth(np.full((8, 8), 1000, np.uint16), np.diag([8.0, 8, 1]), np.eye(4))
    missing = tmp_path / "no" / "such.h5"
    with pytest.raises(ValueError, match="cannot write the checkpoint there: folder .* does not exist"):
        fusion.save_checkpoint(str(missing))
    with pytest.raises(ValueError, match="the checkpoint is written as .h5 or .hdf5"):
        fusion.save_checkpoint(str(tmp_path / "c.txt"))
    assert "HDF5-DIAG" not in capfd.readouterr().err


def test_bad_settings_raise():
    with pytest.raises(rangefuse.InputError, match="voxel"):
        rangefuse.Fusion(voxel=0)
    with pytest.raises(ValueError, match="unknown setting 'envelop'"):
        rangefuse.Fusion(voxel=0.01, envelop=2)
    with pytest.raises(ValueError, match="method"):
        rangefuse.Fusion(voxel=0.01, method="tsdf")


TWO_RANKS = """
import sys
from mpi4py import MPI
import numpy as np
sys.path.insert(0, {here!r})
import test_fusion
vertices, faces, colours = test_fusion.fuse_bunny(MPI.COMM_WORLD)
listed = test_fusion.fuse_bunny_by_its_list(MPI.COMM_WORLD)
if MPI.COMM_WORLD.rank == 0:
    np.savez({out!r}, vertices=vertices, faces=faces, listed_vertices=listed[0],
             listed_faces=listed[1])
else:
    assert len(vertices) == 0 and len(faces) == 0 and len(listed[0]) == 0
"""


def test_two_ranks_under_mpirun_give_the_same_mesh(tmp_path):
    pytest.importorskip("mpi4py")
    script = tmp_path / "two.py"
    out = tmp_path / "two.npz"
    script.write_text(TWO_RANKS.format(here=os.path.dirname(os.path.abspath(__file__)), out=str(out)))
    subprocess.run(["mpirun", "-np", "2", sys.executable, str(script)], check=True, env=os.environ)
    vertices, faces, _ = fuse_bunny()
    got = np.load(out)
    assert np.array_equal(got["faces"], faces)
    assert np.array_equal(got["vertices"], vertices)
    assert np.array_equal(got["listed_faces"], faces)
    assert np.array_equal(got["listed_vertices"], vertices)


def test_a_depth_folder_gives_the_commands_mesh(tmp_path):
    seq, out = tmp_path / "seq", tmp_path / "seq.ply"
    subprocess.run([BIN, "scan", "--mesh", os.path.join(DATA, "bunny", "bun_zipper.ply"),
                    "--scale", "10", "--views", "8", "--width", "96",
                    "--height", "72", "--voxel", "0.02", "--noise", "0.5", "--path", "orbit",
                    "--texture", "1", "--format", "tum", "--out", str(seq)],
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run([BIN, "fuse", "--scans", str(seq), "--voxel", "0.02", "--out", str(out),
                    "--quiet"], check=True)
    fusion = rangefuse.Fusion(voxel=0.02)
    frames = rangefuse.read_frames(str(seq))
    assert len(frames) == 8
    for depth, colour, K, scale, pose, _ in frames:
        assert colour is not None
        fusion.add_depth(rangefuse.read_depth(depth), K, pose, colour=rangefuse.read_colour(colour),
                         depth_scale=scale)
    vertices, faces, colours = fusion.mesh()
    ply_vertices, ply_faces = read_ply(out)
    assert len(faces) > 1000 and colours is not None and colours.shape == vertices.shape
    assert np.array_equal(faces, ply_faces)
    assert np.array_equal(vertices.astype(np.float32), ply_vertices)


def quaternion_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def test_tracks_a_depth_stream_as_the_command_does(tmp_path):
    truth, stream = tmp_path / "truth", tmp_path / "stream"
    subprocess.run([BIN, "scan", "--mesh", os.path.join(DATA, "bunny", "bun_zipper.ply"),
                    "--scale", "10", "--views", "240", "--width", "160", "--height", "120",
                    "--voxel", "0.01", "--path", "handheld", "--noise", "0.5", "--depth-noise",
                    "--format", "tum", "--out", str(truth)], check=True, stdout=subprocess.DEVNULL)
    stream.mkdir()
    for name in ["depth", "camera_intrinsic.json"]:  # no trajectory: tracked
        os.symlink(truth / name, stream / name)
    # The first 40 frames of the hand-held path (a sixth of it).
    lines = (truth / "depth.txt").read_text().splitlines()
    header = [l for l in lines if l.startswith("#")]
    (stream / "depth.txt").write_text("\n".join(header + [l for l in lines if not l.startswith("#")][:40]) + "\n")
    subprocess.run([BIN, "fuse", "--scans", str(stream), "--voxel", "0.01", "--quiet",
                    "--out", str(tmp_path / "c.ply"), "--trajectory-out", str(tmp_path / "c.txt")],
                   check=True)
    fusion = rangefuse.Fusion(voxel=0.01)
    tracked = []
    for depth, colour, K, scale, pose, time in rangefuse.read_frames(str(stream)):
        assert pose is None
        r = fusion.track(rangefuse.read_depth(depth), K, depth_scale=scale, time=time)
        assert r["fused"], r["why"]
        tracked.append(r["pose"])
    command = np.loadtxt(tmp_path / "c.txt")
    assert len(command) == len(tracked) == 40
    for row, pose in zip(command, tracked):  # the command's trajectory, to rounding in its text
        assert np.abs(row[1:4] - pose[:3, 3]).max() < 1e-5
        assert np.abs(quaternion_matrix(row[4:]) - pose[:3, :3]).max() < 1e-5
    # Against the truth, in the first camera's frame: within the command's bound (0.6 voxel).
    gt = np.loadtxt(truth / "groundtruth.txt")[:40]
    first = np.eye(4)
    first[:3, :3], first[:3, 3] = quaternion_matrix(gt[0, 4:]), gt[0, 1:4]
    errors = []
    for row, pose in zip(gt, tracked):
        t = np.linalg.inv(first) @ np.append(row[1:4], 1)
        errors.append(np.linalg.norm(t[:3] - pose[:3, 3]))
    assert np.sqrt(np.mean(np.square(errors))) < 0.006
    vertices, faces, _ = fusion.mesh()
    ply_vertices, ply_faces = read_ply(tmp_path / "c.ply")
    assert np.array_equal(faces, ply_faces)
    assert np.array_equal(vertices.astype(np.float32), ply_vertices)
    # A list without poses is not added: its frames are tracked.
    with pytest.raises(ValueError, match="without a trajectory.*track them"):
        rangefuse.Fusion(voxel=0.01).add_scans(str(stream))


def test_a_stream_is_tracked_or_posed_not_both():
    K = np.array([[100.0, 0, 39.5], [0, 100, 29.5], [0, 0, 1]])
    fusion = rangefuse.Fusion(voxel=0.01)
    fusion.add_depth(np.full((60, 80), 2000, np.uint16), K, np.eye(4))
    with pytest.raises(ValueError, match="given frames with their poses; track in another"):
        fusion.track(np.full((60, 80), 2000, np.uint16), K)


def test_a_checkpoint_resumes_and_the_command_meshes_it(tmp_path):
    K = np.array([[150.0, 0, 59.5], [0, 150, 59.5], [0, 0, 1]])
    fusion = rangefuse.Fusion(voxel=0.01)
    for eye in np.vstack([np.eye(3), -np.eye(3)]) * 2.0:
        pose = looking_at_origin(eye)
        fusion.add_depth(sphere_depth(K, pose, 120, 0.5), K, pose)
    checkpoint = tmp_path / "sphere.h5"
    fusion.save_checkpoint(str(checkpoint))
    vertices, faces, _ = fusion.mesh()
    resumed = rangefuse.Fusion.resume(str(checkpoint))
    assert resumed.frames == 6
    again, again_faces, _ = resumed.mesh()
    assert np.array_equal(again, vertices) and np.array_equal(again_faces, faces)
    with pytest.raises(ValueError, match="finished field"):
        resumed.add_depth(np.full((120, 120), 1000, np.uint16), K, np.eye(4))
    subprocess.run([BIN, "mesh", str(checkpoint), "--out", str(tmp_path / "m.ply")], check=True,
                   stdout=subprocess.DEVNULL)
    ply_vertices, ply_faces = read_ply(tmp_path / "m.ply")
    assert np.array_equal(ply_faces, faces)
    assert np.array_equal(ply_vertices, vertices.astype(np.float32))


def test_a_coloured_stream_needs_colour_in_every_frame():
    K = np.array([[100.0, 0, 39.5], [0, 100, 29.5], [0, 0, 1]])
    fusion = rangefuse.Fusion(voxel=0.01)
    depth = np.full((60, 80), 2000, np.uint16)
    first = fusion.track(depth, K, colour=np.full((60, 80, 3), 200, np.uint8))
    assert first["fused"] and np.array_equal(first["pose"], np.eye(4))
    with pytest.raises(ValueError, match="frame_1: has no colour image, but the stream's first"):
        fusion.track(depth, K)
