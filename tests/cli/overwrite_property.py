#!/usr/bin/env python3
"""Property: no fuse run ever overwrites a file it reads.

Random command lines give each output (--out, --report, --preview, --poses-out, --checkpoint)
either a fresh file or another name of an input (the scan list, a scan, the options file, a
checkpoint resumed) or of another output: through a symbolic link, a hard link, "./" or "..".
After every run each input is byte for byte as before; a run is refused exactly when some
output aliases an input or another output (or is named with another format's extension), and
the refusal names the path it was given.
"""
import hashlib
import os
import random
import subprocess
import sys
import tempfile

BIN = sys.argv[1]
ROLES = {"out": ".ply", "report": ".json", "preview": ".png", "poses-out": ".conf",
         "checkpoint": ".h5"}


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def run(args):
    return subprocess.run([BIN] + args, capture_output=True, text=True, timeout=300)


def main():
    rng = random.Random(56)
    with tempfile.TemporaryDirectory() as tmp:
        sub = os.path.join(tmp, "sub")
        os.makedirs(sub)
        made = run(["scan", "--shape", "sphere", "--views", "4", "--width", "40", "--height", "30",
                    "--voxel", "1", "--out", os.path.join(tmp, "set")])
        assert made.returncode == 0, made.stderr
        scans = os.path.join(tmp, "set", "truth.conf")
        ini = os.path.join(tmp, "run.ini")
        with open(ini, "w") as f:
            f.write("voxel = 2\n")
        resumed = os.path.join(tmp, "resumed.h5")
        first = run(["fuse", "--scans", scans, "--voxel", "2", "--quiet", "--out",
                     os.path.join(tmp, "first.ply"), "--checkpoint", resumed])
        assert first.returncode == 0, first.stderr
        scan_files = sorted(os.path.join(tmp, "set", n) for n in os.listdir(os.path.join(tmp, "set"))
                            if n.startswith("scan") and n.endswith(".ply"))
        inputs = [scans, ini, resumed] + scan_files

        def alias_of(path, k):
            """Another name of `path`: a link of either kind, or a detour through sub/."""
            kind = rng.choice(["symlink", "hardlink", "dot", "dotdot"])
            folder, name = os.path.split(path)
            if kind == "symlink":
                link = os.path.join(tmp, "alias%d_%s" % (k, name))
                os.symlink(path, link)
                return link
            if kind == "hardlink" and os.path.exists(path):
                link = os.path.join(sub, "hard%d_%s" % (k, name))
                os.link(path, link)
                return link
            if kind == "dot":
                return os.path.join(folder, ".", name)
            return os.path.join(sub, "..", os.path.relpath(path, tmp))

        refused = ran = aliased = 0
        for trial in range(40):
            resuming = rng.random() < 0.3
            read = inputs if resuming else [p for p in inputs if p != resumed]
            before = {p: digest(p) for p in read}
            args = ["fuse", "--scans", scans, "--config", ini, "--quiet", "--overwrite"]
            if resuming:
                args += ["--resume", resumed]
            chosen = {}
            for role, ext in ROLES.items():
                if rng.random() < 0.4:
                    continue
                draw = rng.random()
                if draw < 0.2:
                    target = rng.choice(inputs)
                elif draw < 0.3 and chosen:
                    target = rng.choice(list(chosen.values()))[1]
                else:
                    target = os.path.join(tmp, "new%d%s" % (trial, role.replace("-", "")) + ext)
                path = alias_of(target, trial * 10 + len(chosen)) if draw < 0.3 else target
                chosen[role] = (path, target)
            if "out" not in chosen:
                chosen["out"] = (os.path.join(tmp, "new%dout.ply" % trial),) * 2
            for role, (path, _) in chosen.items():
                args += ["--" + role, path]
            targets = [os.path.realpath(t) for _, t in chosen.values()]
            updated = chosen.get("checkpoint", (None, None))[1] == resumed  # in place: allowed
            clash = any(os.path.realpath(t) in map(os.path.realpath, read)
                        for role, (_, t) in chosen.items()
                        if not (role == "checkpoint" and updated)) \
                or len(set(targets)) < len(targets) \
                or any(not p.endswith(ROLES[role]) for role, (p, _) in chosen.items())
            result = run(args)
            after = {p: digest(p) for p in read if not (p == resumed and updated)}
            before = {p: d for p, d in before.items() if p in after}
            assert after == before, "trial %d overwrote an input: %s\n%s" % (
                trial, " ".join(args), result.stderr)
            if clash:
                assert result.returncode != 0, "trial %d ran with an alias: %s" % (
                    trial, " ".join(args))
                named = [p for p, _ in chosen.values() if p in result.stderr]
                assert named, "trial %d: the refusal names no path given: %s" % (
                    trial, result.stderr)
                refused += 1
                aliased += "would overwrite" in result.stderr or "given as both" in result.stderr
            else:
                assert result.returncode == 0, "trial %d failed: %s\n%s" % (
                    trial, " ".join(args), result.stderr)
                ran += 1
            for p in list(os.listdir(tmp)) + [os.path.join("sub", n) for n in os.listdir(sub)]:
                full = os.path.join(tmp, p)
                if p.startswith(("alias", "sub/hard")) or p.startswith("new"):
                    os.remove(full)
        assert aliased >= 5 and ran >= 5, (refused, aliased, ran)
        print("%d runs refused (%d for an alias), %d ran; no input was ever changed" %
              (refused, aliased, ran))
        print("1 passed, 0 failed")


if __name__ == "__main__":
    main()
