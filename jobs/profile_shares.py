#!/usr/bin/env python3
"""Shares of a perf profile by stage of a fuse, as docs/benchmarks.md tables them.

Usage: python3 jobs/profile_shares.py PERF_DATA
Reads `perf report --no-children --sort dso,sym` of PERF_DATA and prints a markdown table:
each stage's share of all samples (both ranks) and its largest symbols. A symbol goes to the
first stage whose patterns it matches; the library's symbols that match none are "other".
"""
import re
import subprocess
import sys

# (stage, patterns of a symbol or of its library). Order matters: first match wins.
STAGES = [
    ("solve and rasterisation, per voxel",
     ["rasterizeSlab", "solveFeet", "rasterizeRows", "::accumulate", "criticalPoints",
      "rootBrackets", "bracketedRoot", "slopeKeepsSign", "cubicRootsInRange", "solvePrismFoot",
      "rootBetween", "countBrickUpdates", "integrateSlab"]),
    ("prism set-up in the adding step, per prism",
     ["PrismRows", "PrismCubic", "scanPrism", "touchesOwnedBrick", "cutSlabs", "triangleNoise"]),
    ("planning, per prism",
     ["prismCost", "addPrismWork", "prismBounds", "addBrickWork", "llround", "addWork",
      "reduceBrickWork", "layoutFromWork", "expectedUpdates"]),
    ("routing, per prism",
     ["trianglesByRank", "routeScan", "routeTaken", "routeRounds", "BrickLayout::mayOwn"]),
    ("fitting a tracked frame: control points and their sums",
     ["locateVoxel", "PlaneSums", "planeSums", "sampleVoxel", "ControlRouting",
      "correspondenceSums", "solveWellPosed"]),
    ("growing a tracked field and splitting it",
     ["GrowingBricks", "BrickStore::grow", "neighbourCodes", "BrickLayout::find"]),
    ("compact and packed frames",
     ["unpackPart", "compactScan", "packPart", "packLimits", "packTriangles", "unpackTriangles",
      "unpackLimits", "usedVertices", "packWhole", "unpackedScan", "packedScan", "subScan",
      "quantised", "normalCode", "normalOf"]),
    ("prism limits, at read",
     ["crossingBeyond", "truncateAtEdgeSurface", "facesSensor", "computePrismLimits",
      "EnvelopeClearance", "makePrism"]),
    ("reading: triangles, normals, joins",
     ["filteredVertexNormals", "keepsTriangle", "joinFlatBlocks", "triangulateGrid",
      "orientedSurface", "buildScanSurface", "longerThan", "cellTexels", "triangleTexels"]),
    ("reading: depth to points, merging, smoothing",
     ["mergeCells", "depthGrid", "smoothDepths", "blockMean", "centralCell", "readScanGrid",
      "pointBounds", "placeScan"]),
    ("reading: noise and medians",
     ["RangeNoise", "lateralAndGridSpacing", "lateralSpacing", "gridSpacing", "nthSmallest",
      "smallestAmongKeys", "digitCounts", "medianNeighbour", "__ieee754_log", "binSigma"]),
    ("PNG decoding (zlib, libpng)", ["libpng", "libz.so", "inflate", "png_"]),
    ("mesh", ["marchingCubes", "MarchingCubes", "extractBlock", "meshField", "stitch", "Stitch",
              "DistributedMesh", "writePly", "MeshPart"]),
    ("MPI library", ["libmpi", "libopen-pal", "libopen-rte", "mca_", "libpmix", "libucs",
                     "libfabric", "libevent"]),
    ("kernel (waiting ranks yielding, page faults)", ["[kernel", "[k]"]),
    ("libc copies and allocation, vectors' growth",
     ["libc.so", "libstdc++", "libm.so", "ld-linux", "::_M_"]),
]


def report(path):
    text = subprocess.run(
        ["perf", "report", "-i", path, "--no-children", "--sort", "dso,sym", "-n", "--stdio"],
        capture_output=True, text=True, check=True).stdout
    rows = []
    for line in text.splitlines():
        m = re.match(r"\s*([0-9.]+)%\s+(\d+)\s+(\S+)\s+\[(.)\]\s+(.*)", line)
        if m:
            rows.append((int(m.group(2)), m.group(3), m.group(4), m.group(5).strip()))
    return rows


def short(symbol):
    """The function's name (Class::method for a member): namespaces, template arguments and
    parameters dropped."""
    s = symbol.replace("(anonymous namespace)::", "")
    while True:
        t = re.sub(r"<[^<>]*>", "", s)
        if t == s:
            break
        s = t
    s = s.split("(")[0]
    parts = [p for p in s.split("::") if p]
    if len(parts) >= 2 and parts[-2][:1].isupper():
        return "::".join(parts[-2:])
    return parts[-1] if parts else symbol


def main():
    rows = report(sys.argv[1])
    total = sum(n for n, *_ in rows)
    stages = {name: {} for name, _ in STAGES}
    stages["other"] = {}
    for n, dso, kind, sym in rows:
        where = "other"
        for name, patterns in STAGES:
            if any(p in sym or p in dso or (p == "[k]" and kind == "k") for p in patterns):
                where = name
                break
        key = short(sym) if where not in ("PNG decoding (zlib, libpng)", "MPI library") else dso
        stages[where][key] = stages[where].get(key, 0) + n
    print(f"Shares of both ranks' {total} samples:\n")
    print("| where | share | largest symbols |")
    print("|---|---|---|")
    order = sorted(stages.items(), key=lambda kv: -sum(kv[1].values()))
    for name, symbols in order:
        count = sum(symbols.values())
        if count == 0:
            continue
        top = sorted(symbols.items(), key=lambda kv: -kv[1])[:5]
        named = ", ".join(f"`{s}` {100 * c / total:.1f}" for s, c in top)
        print(f"| {name} | {100 * count / total:.1f} % | {named} |")


if __name__ == "__main__":
    main()
