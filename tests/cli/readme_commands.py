"""Prints the commands of a Markdown file's indented code blocks that run rangefuse (or make its
output folders), one a line: continuation lines joined, comments and optional [--flags] dropped.
With --small, depth frames and stations are drawn at half the printed resolution."""
import re
import sys

RUNNABLE = re.compile(r"^(build/rangefuse|mpirun|mkdir)\b")


def commands(text):
    lines = text.split("\n")
    i = 0
    while i < len(lines):
        m = re.match(r"^ {4,}(\S.*)$", lines[i])
        i += 1
        if not m:
            continue
        command = m.group(1)
        while command.endswith("\\") and i < len(lines):
            command = command[:-1].rstrip() + " " + lines[i].strip()
            i += 1
        command = re.sub(r"\s+#.*$", "", command)
        command = re.sub(r"\s*\[--[^\]]*\]", "", command)
        if RUNNABLE.match(command):
            yield command


def smaller(command):
    """Half the width and height of synthetic pictures: the same steps at a quarter the cost."""
    return re.sub(r"--(width|height) (\d+)", lambda m: f"--{m.group(1)} {int(m.group(2)) // 2}",
                  command)


if __name__ == "__main__":
    small = "--small" in sys.argv[2:]
    for c in commands(open(sys.argv[1], encoding="utf-8").read()):
        print(smaller(c) if small else c)
