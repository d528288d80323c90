#!/usr/bin/env python3
"""One table of the headline figures from the tables benchmark_all.sh saved in OUT_DIR.

Usage: python3 jobs/summarize_benchmarks.py OUT_DIR

Reads the Markdown tables each benchmark script printed (OUT_DIR/NAME.md) and prints one row
per figure: what, on which set, rangefuse's value, the peer's (measured in the same run) and
the ratio. A script that did not run, or a table without the row, is left out.
"""
import os
import re
import sys


def tables(path):
    """Every Markdown table of a file, as lists of {header: cell} rows. A table starts at a
    header line followed by |---|; lines that are not table rows (log lines a script printed
    in the middle) are skipped without ending it."""
    if not os.path.exists(path):
        return []
    lines = [l.strip() for l in open(path, encoding="utf-8")]
    found, header = [], None
    for i, line in enumerate(lines):
        if not line.startswith("|") or line.startswith("|---"):
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        if i + 1 < len(lines) and lines[i + 1].startswith("|---"):
            header = cells
            found.append([])
        elif header is not None:
            found[-1].append(dict(zip(header, cells)))
    return found


def number(cell, index=0):
    """The index-th number in a cell ("8.2", "455 / 456" -> 455), or None."""
    values = re.findall(r"-?\d+(?:\.\d+)?", cell or "")
    return float(values[index]) if len(values) > index else None


def ratio(ours, peer):
    return "%.2f" % (ours / peer) if ours is not None and peer else "—"


def show(value, digits=2):
    return "—" if value is None else ("%.*f" % (digits, value))


def summary(out):
    rows = []  # (figure, set, rangefuse, peer, ours / peer)
    for table in tables(os.path.join(out, "benchmark_speed.md"))[:1]:
        for r in table:
            if r.get("input", "").startswith("("):
                continue  # a second run of the same input
            ours, peer = number(r.get("Chamfer (voxel)")), number(r.get("Open3D Chamfer"))
            rows.append(("Chamfer (voxel), Open3D TSDF beside", r["input"], show(ours, 3),
                         show(peer, 3), ratio(ours, peer)))
            whole = number(r.get("read to write / Open3D compute"))
            rows.append(("seconds read to write / Open3D compute", r["input"], show(whole),
                         "1", show(whole)))
    for table in tables(os.path.join(out, "benchmark_sequence.md"))[:1]:
        ours = next((r for r in table if r["tool"].startswith("rangefuse prism")), None)
        peer = next((r for r in table if r["tool"].startswith("Open3D")), None)
        if ours and peer:
            for key, label, digits in [("seconds read to mesh", "seconds read to mesh", 2),
                                       ("peak memory (MiB)", "peak memory (MiB)", 0),
                                       ("Chamfer (voxel)", "Chamfer (voxel)", 3)]:
                a, b = number(ours[key]), number(peer[key])
                rows.append((label + ", ScalableTSDFVolume beside", "depth sequence, "
                             + ours["tool"], show(a, digits), show(b, digits), ratio(a, b)))
    for table in tables(os.path.join(out, "benchmark_tracking.md"))[:1]:
        for sequence in dict.fromkeys(r["sequence"] for r in table):
            mine = [r for r in table if r["sequence"] == sequence]
            ours = next((r for r in mine if r["tool"] == "rangefuse, 2 ranks"), None)
            peer = next((r for r in mine if r["tool"].startswith("Open3D")), None)
            if ours and peer:
                a, b = number(ours["ATE (mm)"]), number(peer["ATE (mm)"])
                rows.append(("ATE (mm), tracked without poses, Open3D ICP beside", sequence,
                             show(a), show(b), ratio(a, b)))
    for table in tables(os.path.join(out, "benchmark_kitchen.md"))[:1]:
        for r in table:
            a, b = number(r.get("rangefuse ATE")), number(r.get("Open3D ICP ATE"))
            rows.append(("ATE (cm), real Kinect, poses hidden, Open3D ICP beside",
                         "7-Scenes kitchen, %s, frames %s" % (r["set"], r["frames"]), show(a),
                         show(b), ratio(a, b)))
            a, b = number(r.get("frames/s")), number(r.get("Open3D frames/s"))
            rows.append(("frames/s, real Kinect, Open3D ICP beside",
                         "7-Scenes kitchen, %s" % r["set"], show(a, 1), show(b, 1), ratio(a, b)))
            a = number(r.get("updates max/mean"))
            if a is not None:
                rows.append(("voxel updates max/mean, tracked real Kinect, 2 ranks",
                             "7-Scenes kitchen, %s" % r["set"], show(a, 3), "", ""))
    for table in tables(os.path.join(out, "benchmark_stream_speed.md"))[:1]:
        memory = []
        for r in table:
            if not r["tool"].startswith("rangefuse prism"):
                continue
            name = "Open3D RGB8" if "colour rgb" in r["tool"] else "Open3D ScalableTSDFVolume"
            peer = next((p for p in table if p["set"] == r["set"] and p["tool"] == name), {})
            label = name.replace("Open3D ScalableTSDFVolume", "ScalableTSDFVolume")
            what = "%s, %s" % (r["set"], r["tool"][len("rangefuse prism, "):])
            ours = number(r.get("seconds read to mesh"))
            theirs = number(peer.get("seconds read to mesh"))
            rows.append(("seconds read to mesh, %s beside" % label, what, show(ours),
                         show(theirs), ratio(ours, theirs)))
            if "--merge-cells" not in r["tool"]:
                ours = number(r.get("peak MiB, all ranks"))
                theirs = number(peer.get("peak MiB, all ranks"))
                memory.append(("peak memory (MiB, all ranks), %s beside" % label, what,
                               show(ours, 0), show(theirs, 0), ratio(ours, theirs)))
        rows.extend(memory)
    for table in tables(os.path.join(out, "benchmark_heldout.md"))[:1]:
        for name in dict.fromkeys(r["set"] for r in table):
            mine = [r for r in table if r["set"] == name]
            peer = next((r for r in mine if r["tool"].startswith("Open3D")), None)
            for r in mine:
                if peer and r["tool"].startswith("rangefuse"):
                    a, b = number(r["median distance (mm)"]), number(peer["median distance (mm)"])
                    rows.append(("median distance (mm) to frames left out, Open3D beside",
                                 "7-Scenes kitchen, %s, %s" % (name, r["tool"]), show(a),
                                 show(b), ratio(a, b)))
    memory = tables(os.path.join(out, "benchmark_memory.md"))
    if memory:
        peaks = {r["ranks"]: max(number(x) for x in r["peak memory per rank (MiB)"].split("/"))
                 for r in memory[0] if r["ranks"].isdigit()}
        for n in sorted(peaks, key=int):
            if n != "1" and "1" in peaks:
                rows.append(("peak memory per rank (MiB), %s ranks against 1" % n,
                             "48 x 1024², 0.5 mm", show(peaks[n], 0), show(peaks["1"], 0),
                             ratio(peaks[n], peaks["1"])))
    for table in tables(os.path.join(out, "benchmark.md"))[:1]:
        for r in table:
            if r.get("ranks") == "2" and number(r.get("speed-up 2 vs 1 (job)")):
                rows.append(("speed-up, 2 ranks against 1 (job)",
                             "%s, %s, %s" % (r["dataset"], r["method"], r["voxel"]),
                             r["speed-up 2 vs 1 (job)"], "", ""))
    for table in tables(os.path.join(out, "benchmark_speedup.md"))[:1]:
        for r in table:
            rows.append(("speed-up, 2 ranks against 1 (rangefuse's clock, best of 3)", r["set"],
                         r["speed-up"], "", ""))
    weak = tables(os.path.join(out, "benchmark_weak_scaling.md"))
    if weak and weak[0]:
        last = weak[0][-1]
        rows.append(("weak scaling: peak per rank, %s ranks against 1" % last["ranks"],
                     "a bunny copy a rank", last["peak per rank, largest (MiB)"],
                     weak[0][0]["peak per rank, largest (MiB)"], last["/ 1 rank"]))
    print("| figure | set | rangefuse | peer or base | ratio |")
    print("|---|---|---|---|---|")
    for row in rows:
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    summary(sys.argv[1] if len(sys.argv) > 1 else "benchmarks-out")
