#!/usr/bin/env bash
# No run overwrites what it reads: every output aliasing an input (scan list, a scan it names,
# a sequence's frames, the checkpoint resumed, the options file) or another output is refused
# before any work, naming both files, with the input byte for byte as it was; an existing
# checkpoint is replaced only with --overwrite; outputs are written in the format their name
# says or refused; wrong figures and misleading messages of issue 56 are checked too.
set -euo pipefail
bin=$1
data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# refused NAME FILE_KEPT TEXT... -- COMMAND...: the command exits non-zero, its message holds
# every TEXT, and FILE_KEPT is byte-identical afterwards.
refused() {
  local name=$1 kept=$2 texts=() before
  shift 2
  while [[ $1 != -- ]]; do texts+=("$1"); shift; done
  shift
  before=$(sha256sum "$kept" | cut -d' ' -f1)
  if "$@" >"$tmp/out.txt" 2>&1; then fail "$name: ran ($(tail -2 "$tmp/out.txt"))"; fi
  for t in "${texts[@]}"; do
    grep -qF -- "$t" "$tmp/out.txt" || fail "$name: message lacks '$t': $(cat "$tmp/out.txt")"
  done
  [[ $(sha256sum "$kept" | cut -d' ' -f1) == "$before" ]] || fail "$name: $kept changed"
  echo "ok   $name"
}

cp -r "$data/bunny" "$tmp/b"
fuse=(mpirun -np 2 "$bin" fuse --quiet)
bunny=("${fuse[@]}" --voxel 0.004)
"${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m.ply" --checkpoint "$tmp/c.h5"

# Outputs over inputs.
refused "--out over the checkpoint resumed" "$tmp/c.h5" "$tmp/c.h5" "checkpoint resumed" -- \
  "${bunny[@]}" --resume "$tmp/c.h5" --out "$tmp/c.h5"
refused "mesh --out over its checkpoint" "$tmp/c.h5" "$tmp/c.h5" "would overwrite" -- \
  mpirun -np 2 "$bin" mesh "$tmp/c.h5" --out "$tmp/./c.h5"
refused "--report over the scan list" "$tmp/b/bun.conf" "would overwrite '$tmp/b/bun.conf' (the scan list)" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m2.ply" --report "$tmp/b/bun.conf"
refused "--out over a raw scan" "$tmp/b/bun000.ply" "$tmp/b/bun000.ply" "scan list's file" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/b/bun000.ply"
ln -s "$tmp/b/bun045.ply" "$tmp/link.ply"
refused "--out through a symbolic link to a scan" "$tmp/b/bun045.ply" "$tmp/link.ply" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/link.ply"
ln "$tmp/b/bun090.ply" "$tmp/hard.ply"
refused "--poses-out over a hard link to a scan" "$tmp/b/bun090.ply" "$tmp/hard.ply" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m2.ply" --poses-out "$tmp/hard.ply"
mkdir -p "$tmp/d"
refused "--checkpoint over the XDMF mesh's data" "$tmp/c.h5" "given as both" "(the mesh data)" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/d/x.xdmf" --checkpoint "$tmp/d/../d/x.h5"
printf 'scans = %s\n' "$tmp/b/bun.conf" >"$tmp/run.ini"
refused "--report over the options file" "$tmp/run.ini" "options file" -- \
  "${bunny[@]}" --config "$tmp/run.ini" --out "$tmp/m2.ply" --report "$tmp/run.ini"
refused "perturb over its own list" "$tmp/b/bun.conf" "would overwrite" -- \
  "$bin" perturb --scans "$tmp/b/bun.conf" --voxel 0.001 --out "$tmp/b/bun.conf"
refused "render over the list" "$tmp/b/bun.conf" "would overwrite" -- \
  "$bin" render --scans "$tmp/b/bun.conf" --voxel 0.004 --out "$tmp/b/../b/bun.conf"
refused "eval --json-out over the reference" "$tmp/b/bun_zipper.ply" "(the reference)" -- \
  "$bin" eval --mesh "$tmp/m.ply" --reference "$tmp/b/bun_zipper.ply" --voxel 0.004 \
  --json-out "$tmp/b/./bun_zipper.ply"
cp "$tmp/b/bun_zipper.ply" "$tmp/d/truth.ply"
refused "scan --mesh inside --out" "$tmp/d/truth.ply" "inside --out" -- \
  "$bin" scan --mesh "$tmp/d/truth.ply" --voxel 0.004 --views 2 --out "$tmp/d"

# A depth sequence's frames, and a followed folder.
"$bin" scan --mesh "$data/bunny/bun_zipper.ply" --scale 10 --views 40 --width 80 --height 60 \
  --voxel 0.02 --path handheld --format redwood --out "$tmp/seq" >/dev/null
refused "--trajectory-out over the sequence's trajectory" "$tmp/seq/trajectory.log" "scan list's file" -- \
  "${fuse[@]}" --scans "$tmp/seq" --voxel 0.02 --out "$tmp/s.ply" --trajectory-out "$tmp/seq/trajectory.log"
refused "--preview inside a followed folder" "$tmp/seq/trajectory.log" "inside" "followed folder" -- \
  "${fuse[@]}" --scans "$tmp/seq" --voxel 0.02 --track on --follow --follow-timeout 1 \
  --out "$tmp/s.ply" --preview "$tmp/seq/depth/p.png"

# A checkpoint: resumed in place (updated by renames), else replaced only with --overwrite.
refused "an existing --checkpoint not resumed" "$tmp/c.h5" "exists" "--resume $tmp/c.h5" "--overwrite" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m2.ply" --checkpoint "$tmp/c.h5"
"${bunny[@]}" --resume "$tmp/c.h5" --checkpoint "$tmp/c.h5" --out "$tmp/m3.ply"
cmp -s "$tmp/m.ply" "$tmp/m3.ply" || fail "resumed in place: a different mesh"
"$bin" info "$tmp/c.h5" >/dev/null || fail "resumed in place: the checkpoint is no longer one"
"${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m4.ply" --checkpoint "$tmp/c.h5" --overwrite
cmp -s "$tmp/m.ply" "$tmp/m4.ply" || fail "--overwrite: a different mesh"
echo "ok   a checkpoint resumed in place, and replaced with --overwrite"

# Formats by name.
refused "--out .obj" "$tmp/c.h5" "t.obj: the mesh is written as .ply or .xdmf" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/t.obj"
refused "--preview .jpg" "$tmp/c.h5" "the preview is written as .png" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/t.ply" --preview "$tmp/t.jpg"
refused "render --out .jpg" "$tmp/c.h5" "the picture is written as .png" -- \
  "$bin" render --checkpoint "$tmp/c.h5" --out "$tmp/t.jpg"
refused "mesh --out .obj" "$tmp/c.h5" "is written as .ply or .xdmf" -- \
  "$bin" mesh "$tmp/c.h5" --out "$tmp/t.obj"
[[ ! -e $tmp/t.obj && ! -e $tmp/t.jpg ]] || fail "a refused format was written"
mpirun -np 2 "$bin" mesh "$tmp/c.h5" --out "$tmp/x.xdmf" >/dev/null
head -c 5 "$tmp/x.xdmf" | grep -q '<?xml' || fail "mesh --out .xdmf is not XDMF"
[[ $(head -c 4 "$tmp/x.h5" | od -An -c | tr -d ' ') == '211HDF' ]] || fail "mesh --out .xdmf: no HDF5 data"
echo "ok   mesh --out .xdmf writes XDMF with its HDF5 data"

# --scan-format against the folder's own files.
refused "--scan-format tum on a Redwood folder" "$tmp/seq/trajectory.log" \
  "--scan-format tum does not fit" "numbered (depth/000000.png)" -- \
  "${fuse[@]}" --scans "$tmp/seq" --voxel 0.02 --scan-format tum --out "$tmp/s.ply"

# Help: a misspelt option is answered with the one meant.
refused "--color" "$tmp/c.h5" "did you mean --colour?" -- "$bin" fuse --color rgb
refused "--max-depth" "$tmp/c.h5" "did you mean --depth-max?" -- "$bin" fuse --max-depth 3
for format in .conf .ptx .e57 TUM Redwood Open3D; do
  "$bin" --help | grep -qF -- "$format" || fail "the top-level help does not list $format"
done
echo "ok   the top-level help lists every input format"

# eval: one trajectory as TUM (frame times k/30 s) and as .log matches on every pose.
python3 - "$tmp/seq/trajectory.log" "$tmp/seq.txt" <<'EOF'
import math, sys
rows = [[float(v) for v in l.split()] for l in open(sys.argv[1]) if l.strip()]
with open(sys.argv[2], "w") as out:
    for k in range(len(rows) // 5):
        R = [r[:3] for r in rows[5 * k + 1:5 * k + 4]]
        t = [r[3] for r in rows[5 * k + 1:5 * k + 4]]
        trace = R[0][0] + R[1][1] + R[2][2]
        if trace > -0.9:
            w = math.sqrt(1 + trace) / 2
            q = [(R[2][1] - R[1][2]) / (4 * w), (R[0][2] - R[2][0]) / (4 * w),
                 (R[1][0] - R[0][1]) / (4 * w), w]
        else:  # near a half turn: from the largest diagonal term
            i = max(range(3), key=lambda a: R[a][a])
            j, l = (i + 1) % 3, (i + 2) % 3
            s = math.sqrt(1 + R[i][i] - R[j][j] - R[l][l]) * 2
            q = [0.0] * 4
            q[i], q[j], q[l] = s / 4, (R[j][i] + R[i][j]) / s, (R[l][i] + R[i][l]) / s
            q[3] = (R[l][j] - R[j][l]) / s
        print("%.6f %.17g %.17g %.17g %.17g %.17g %.17g %.17g" % (k / 30, *t, *q), file=out)
EOF
"$bin" eval --trajectory "$tmp/seq.txt" --reference "$tmp/seq/trajectory.log" >"$tmp/eval.txt"
grep -q "poses matched      40 of 40 by time" "$tmp/eval.txt" || fail "mixed eval: $(cat "$tmp/eval.txt")"
ate=$(sed -n 's/^ATE RMSE *\([^ ]*\) m.*/\1/p' "$tmp/eval.txt")
awk "BEGIN { exit !($ate < 1e-6) }" || fail "mixed eval: ATE $ate, not 0"
echo "ok   one trajectory as TUM and as .log: 40 of 40 poses, ATE $ate m"

# info prints a depth frame's pose as its trajectory does (camera to world, qx qy qz qw).
"${fuse[@]}" --scans "$tmp/seq" --voxel 0.02 --track off --out "$tmp/s.ply" --checkpoint "$tmp/s.h5"
"$bin" info "$tmp/s.h5" >"$tmp/info.txt"
first=$(grep -m1 'depth/000000.png' "$tmp/info.txt")
expected=$(head -1 "$tmp/seq.txt" | awk '{ printf "t %.6g %.6g %.6g  q %.6g %.6g %.6g %.6g", $2, $3, $4, $5, $6, $7, $8 }')
python3 - "$first" "$expected" <<'EOF' || fail "info: '$first', the trajectory says '$expected'"
import sys, re
got = [float(v) for v in re.findall(r"[-0-9.e+]+", sys.argv[1].split("  t ")[1].split("(")[0])]
want = [float(v) for v in re.findall(r"[-0-9.e+]+", sys.argv[2])]
q, p = got[3:], want[3:]
sign = -1 if sum(a * b for a, b in zip(q, p)) < 0 else 1  # q and -q are one rotation
assert all(abs(a - b) < 1e-4 for a, b in zip(got[:3], want[:3])), (got, want)
assert all(abs(sign * a - b) < 1e-4 for a, b in zip(q, p)), (got, want)
EOF
echo "ok   info gives the first camera as its trajectory does"

# A tracked run's report has its tracking figures; the stream's voxel is checked.
"${fuse[@]}" --scans "$tmp/seq" --voxel 0.02 --track on --out "$tmp/t.ply" --report "$tmp/t.json"
python3 - "$tmp/t.json" <<'EOF' || fail "tracked report: $(head -c 600 "$tmp/t.json")"
import json, sys
r = json.load(open(sys.argv[1]))
t = r["tracking"]
assert t["frames"] == 40 and t["fused"] + t["lost"] == 40, t
assert 0 < t["inliers"]["median"] <= 1 and t["rms_residual"]["median"] > 0, t
assert sum(rank["prisms"] for rank in r["per_rank"]) > 0, r["per_rank"]
EOF
echo "ok   a tracked run's report gives frames, lost, inliers and residuals, and its prisms"
mpirun -np 2 "$bin" fuse --scans "$tmp/seq" --voxel 10 --track on --skip-lost \
  --out "$tmp/v.ply" >"$tmp/v.txt" 2>&1 || true
grep -q "did you mean 0.01?" "$tmp/v.txt" || fail "--voxel 10 on a stream: $(cat "$tmp/v.txt")"
echo "ok   a stream's voxel is checked against its first frame"

# Ctrl-C (SIGINT, as mpirun forwards it) says how to go on.
setsid mpirun -np 2 "$bin" fuse --scans "$tmp/b/bun.conf" --voxel 0.0005 --out "$tmp/i.ply" \
  --checkpoint "$tmp/i.h5" >"$tmp/i.txt" 2>&1 &
job=$!
for _ in $(seq 100); do grep -q "read" "$tmp/i.txt" 2>/dev/null && break; sleep 0.1; done
kill -INT -- -"$job" 2>/dev/null || true
wait "$job" 2>/dev/null || true
grep -q "interrupted; to go on from the last checkpoint, run the same command with --resume $tmp/i.h5" \
  "$tmp/i.txt" || fail "SIGINT: $(tail -5 "$tmp/i.txt")"
echo "ok   an interrupted run names the checkpoint to resume"
echo "all overwrite and wrong-figure checks passed"
