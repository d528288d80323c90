"""Checks the loose scans a composite set's run report marks against the scene's truth.

The composite is a torus about the z axis, a sphere on that axis and a small sphere off it at
(50, 0, -4), radius 8. A scan with no point on the small sphere (at its true pose; a few outliers may fall there) sees a scene
symmetric about the z axis: it must be marked loose, with a turn about z through the axis. A scan
with 100 points or more there must not. Usage: loose_scans.py SET REPORT STDERR
"""
import json
import os
import struct
import sys

SMALL_SPHERE, RADIUS = (50.0, 0.0, -4.0), 8.0


def rotation(x, y, z, w):
    """The rotation whose transpose the .conf's quaternion holds (Stanford convention)."""
    q = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[q[k][i] for k in range(3)] for i in range(3)]


def vertices(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len("end_header\n")
    header = data[:end].decode().splitlines()
    count = int(next(l for l in header if l.startswith("element vertex")).split()[2])
    return [struct.unpack_from("<3f", data, end + 12 * k) for k in range(count)]


def points_on_small_sphere(folder, line):
    f = line.split()
    t = [float(v) for v in f[2:5]]
    R = rotation(*[float(v) for v in f[5:9]])
    near = 0
    for p in vertices(os.path.join(folder, f[1])):
        w = [sum(R[i][k] * p[k] for k in range(3)) + t[i] for i in range(3)]
        near += sum((w[i] - SMALL_SPHERE[i]) ** 2 for i in range(3)) < (RADIUS + 1.5) ** 2
    return near


folder, report, stderr = sys.argv[1:4]
truth = [points_on_small_sphere(folder, l) for l in open(os.path.join(folder, "truth.conf")) if l.split()]
scans = json.load(open(report))["registration"]["scans"]
loose = {s["scan"] for s in scans if s["loose"]}
for s in scans:
    seen = truth[s["scan"]]
    if seen < 10:
        assert s["loose"], ("scan %d saw no asymmetric part but is held" % s["scan"], s)
    if seen >= 100:
        assert not s["loose"], ("scan %d saw the small sphere but is loose" % s["scan"], s)
    if s["loose"]:
        m = s["loose_motion"]
        assert m["kind"] == "turn" and abs(m["direction"][2]) > 0.998, m
        assert abs(m["through"][0]) < 1 and abs(m["through"][1]) < 1, m
assert any(seen < 10 for seen in truth) and any(seen >= 100 for seen in truth), truth
warned = open(stderr).read().count("is held loosely")
assert warned == len(loose), (warned, loose)
# The overlap per pair the progress line counts is the report's.
pairs = json.load(open(report))["registration"]["pairs"]
assert pairs and all(p["a"] < p["b"] for p in pairs), pairs
last = sum(p["last"] >= 50 for p in pairs)
log = open(report.replace(".json", ".log")).read()
assert "[register] overlap: %d pairs of scans overlap" % last in log, (last, log)
print("loose scans %s (points on the small sphere: %s)" % (sorted(loose), truth))
