#!/usr/bin/env bash
# The fused mesh is byte-identical on 1, 2 and 3 ranks.
set -euo pipefail
bin=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for method in prism robust consensus; do
  voxel=0.0015
  [[ $method == consensus ]] && voxel=0.0025
  for n in 1 2 3; do
    mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$data/bunny/bun.conf" --voxel $voxel \
      --method $method --out "$tmp/mesh$n.ply" >"$tmp/log$n"
  done
  cmp "$tmp/mesh1.ply" "$tmp/mesh2.ply"
  cmp "$tmp/mesh1.ply" "$tmp/mesh3.ply"
  echo "$method: 1, 2 and 3 ranks give identical meshes ($(stat -c %s "$tmp/mesh1.ply") bytes)"
done
# Robust fusion of pinhole scans with a patch and outliers (free space from the sight maps).
"$bin" scan --shape composite --views 6 --width 120 --height 90 --voxel 1 --noise 0.5 \
  --outliers 0.01 --patches 1 --out "$tmp/patchy" >/dev/null
for n in 1 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/patchy/truth.conf" --voxel 1 \
    --method robust --threads 2 --out "$tmp/robust$n.ply" >"$tmp/log$n"
done
cmp "$tmp/robust1.ply" "$tmp/robust2.ply"
cmp "$tmp/robust1.ply" "$tmp/robust3.ply"
echo "robust (pinhole, patch): 1, 2 and 3 ranks give identical meshes"
# A depth-camera sequence (TUM folder of 16-bit PNG frames), robust fusion with sight maps.
"$bin" scan --shape composite --views 12 --width 120 --height 90 --voxel 0.01 --scale 0.01 \
  --path orbit --noise 0.5 --depth-noise --outliers 0.01 --format tum --out "$tmp/tum" >/dev/null
for n in 1 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/tum" --voxel 0.01 --method robust \
    --out "$tmp/tum$n.ply" >"$tmp/log$n"
done
cmp "$tmp/tum1.ply" "$tmp/tum2.ply"
cmp "$tmp/tum1.ply" "$tmp/tum3.ply"
echo "depth sequence (TUM, robust): 1, 2 and 3 ranks give identical meshes"
# Scanner stations in one PTX file, dense enough to be merged and read in bands of columns.
"$bin" scan --shape room --path stations --views 2 --width 480 --height 200 --voxel 0.08 \
  --noise 0.3 --format ptx --out "$tmp/room" >/dev/null
for n in 1 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/room/stations.ptx" --voxel 0.08 \
    --band-cells 30000 --out "$tmp/room$n.ply" >"$tmp/log$n"
done
grep -q "with large ones in bands" "$tmp/log1"
cmp "$tmp/room1.ply" "$tmp/room2.ply"
cmp "$tmp/room1.ply" "$tmp/room3.ply"
echo "stations (PTX, merged, in bands): 1, 2 and 3 ranks give identical meshes"
# Registration: identical poses and meshes too.
"$bin" scan --shape composite --views 6 --width 120 --height 90 --voxel 1 --rot-deg 2 \
  --trans-vox 2 --out "$tmp/synth" >/dev/null
for n in 1 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/synth/perturbed.conf" --voxel 1 \
    --register both --max-iterations 5 --max-rounds 2 --out "$tmp/reg$n.ply" \
    --poses-out "$tmp/poses$n.conf" >"$tmp/log$n"
done
cmp "$tmp/poses1.conf" "$tmp/poses2.conf"
cmp "$tmp/poses1.conf" "$tmp/poses3.conf"
cmp "$tmp/reg1.ply" "$tmp/reg2.ply"
cmp "$tmp/reg1.ply" "$tmp/reg3.ply"
echo "registration: 1, 2 and 3 ranks give identical poses and meshes"
# No scan kept in memory: every field re-reads them, and nothing changes.
mpirun --oversubscribe -np 2 "$bin" fuse --scans "$tmp/synth/perturbed.conf" --voxel 1 \
  --register both --max-iterations 5 --max-rounds 2 --scan-memory 0 --out "$tmp/reread.ply" \
  --poses-out "$tmp/reread.conf" >"$tmp/log_reread"
grep -q "scans kept per rank 0" "$tmp/log_reread"
cmp "$tmp/poses1.conf" "$tmp/reread.conf"
cmp "$tmp/reg1.ply" "$tmp/reread.ply"
echo "registration re-reading every scan (--scan-memory 0) gives the same poses and mesh"
# Threads inside the ranks: any count gives the same poses and mesh.
mpirun --oversubscribe -np 2 "$bin" fuse --scans "$tmp/synth/perturbed.conf" --voxel 1 \
  --register both --max-iterations 5 --max-rounds 2 --threads 3 --out "$tmp/threads.ply" \
  --poses-out "$tmp/threads.conf" >"$tmp/log_threads"
cmp "$tmp/poses1.conf" "$tmp/threads.conf"
cmp "$tmp/reg1.ply" "$tmp/threads.ply"
"$bin" fuse --scans "$data/bunny/bun.conf" --voxel 0.0015 --threads 3 --out "$tmp/bunny3.ply" \
  >"$tmp/log_bunny3"
mpirun --oversubscribe -np 1 "$bin" fuse --scans "$data/bunny/bun.conf" --voxel 0.0015 \
  --threads 1 --out "$tmp/bunny1.ply" >"$tmp/log_bunny1"
cmp "$tmp/bunny1.ply" "$tmp/bunny3.ply"
echo "registration and fusion with 3 threads a rank give the same poses and meshes as with 1"
# The XDMF/HDF5 mesh: the same bytes on 1, 2 and 3 ranks, and the PLY mesh's counts.
for n in 1 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$data/bunny/bun.conf" --voxel 0.0015 \
    --out "$tmp/x$n.xdmf" >"$tmp/logx$n"
done
cmp "$tmp/x1.h5" "$tmp/x2.h5"
cmp "$tmp/x1.h5" "$tmp/x3.h5"
cmp <(sed 's/x1\.h5/X.h5/' "$tmp/x1.xdmf") <(sed 's/x3\.h5/X.h5/' "$tmp/x3.xdmf")
vertices=$(grep -a -m1 "^element vertex" "$tmp/bunny1.ply" | cut -d' ' -f3)
faces=$(grep -a -m1 "^element face" "$tmp/bunny1.ply" | cut -d' ' -f3)
grep -q "Dimensions=\"$vertices 3\"" "$tmp/x1.xdmf"
grep -q "NumberOfElements=\"$faces\"" "$tmp/x1.xdmf"
echo "XDMF mesh: 1, 2 and 3 ranks give identical files, with the PLY mesh's $vertices vertices and $faces faces"
