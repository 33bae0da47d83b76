#!/usr/bin/env python3
"""Which way the bodies of a folder of clips face, per action, and the same clips turned about up.

    python3 tools/headings.py table DIR              # per action: frames per heading sector
    python3 tools/headings.py turn DIR OUT DEGREES   # every clip turned about up into OUT

DIR holds motionfork CSV files (`motionfork convert CLIP.bvh CLIP.csv --skeleton bandai`: one row
a frame, columns "Joint.x,Joint.y,Joint.z" in metres, Y up), named as the Bandai clips are
(dataset-N_ACTION_STYLE_NNN.csv). The heading of a frame is the angle on the ground (x, z) of the
line from UpperLeg_R to UpperLeg_L, in degrees, atan2(x, z); `table` samples every 15th frame
(half a second at 30 Hz) from frame 14 and counts them in eight 45-degree sectors centred on
-180, -135, ..., 135. `turn` rotates every joint by DEGREES about the y axis (x' = x cos + z sin,
z' = z cos - x sin: every heading grows by DEGREES) and writes the clips with the same header
lines into a new folder; nothing else changes.

Used for RESULTS.md's "Where the body goes" (issue 27): the capture room's heading per action,
and the test clips turned for `motionfork eval --clips OUT`.
"""

import argparse
import collections
import math
import os
import sys


def read_csv(path):
    """Returns (header lines, columns, frames as lists of floats)."""
    with open(path) as f:
        lines = f.read().splitlines()
    header = [l for l in lines[:2] if l.startswith("#")]
    names = lines[len(header)].split(",")
    rows = []
    for number, line in enumerate(lines[len(header) + 1:], start=len(header) + 2):
        if not line.strip():
            continue
        try:
            values = [float(v) for v in line.split(",")]
        except ValueError:
            sys.exit(f"{path}: line {number}: expected numbers, found {line[:40]!r}")
        if len(values) != len(names):
            sys.exit(f"{path}: line {number}: expected {len(names)} values, found {len(values)}")
        rows.append(values)
    return header, names, rows


def column(names, joint, axis, path):
    key = f"{joint}.{axis}"
    if key not in names:
        sys.exit(f"{path}: expected a column {key}, found {', '.join(names[:6])}, ...")
    return names.index(key)


def action_of(path):
    parts = os.path.basename(path).split("_")
    return parts[1] if len(parts) >= 4 else "?"


def csv_files(folder):
    files = sorted(os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".csv"))
    if not files:
        sys.exit(f"{folder}: no .csv files")
    return files


def table(folder):
    sectors = list(range(-180, 180, 45))
    counts = collections.defaultdict(lambda: [0] * len(sectors))
    for path in csv_files(folder):
        _, names, rows = read_csv(path)
        lx, lz = column(names, "UpperLeg_L", "x", path), column(names, "UpperLeg_L", "z", path)
        rx, rz = column(names, "UpperLeg_R", "x", path), column(names, "UpperLeg_R", "z", path)
        for row in rows[14::15]:
            h = math.degrees(math.atan2(row[lx] - row[rx], row[lz] - row[rz]))
            k = int(((h + 22.5) % 360) // 45)  # sector centred on -180 + 45 k
            counts[action_of(path)][(k + 4) % 8] += 1
    print("action                " + " ".join(f"{s:>6}" for s in sectors))
    for action in sorted(counts):
        print(f"{action:<22}" + " ".join(f"{c:>6}" for c in counts[action]))


def turn(folder, out, degrees):
    if os.path.exists(out) and os.listdir(out):
        sys.exit(f"{out}: exists and is not empty; expected a new folder")
    os.makedirs(out, exist_ok=True)
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    for path in csv_files(folder):
        header, names, rows = read_csv(path)
        xs = [i for i, n in enumerate(names) if n.endswith(".x")]
        for row in rows:
            for i in xs:
                x, z = row[i], row[i + 2]
                row[i], row[i + 2] = c * x + s * z, -s * x + c * z
        tmp = os.path.join(out, os.path.basename(path) + ".part")
        with open(tmp, "w") as f:
            f.write("\n".join(header + [",".join(names)]) + "\n")
            for row in rows:
                f.write(",".join(f"{v:.6f}" for v in row) + "\n")
        os.replace(tmp, os.path.join(out, os.path.basename(path)))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    t = sub.add_parser("table", help="frames per heading sector, per action")
    t.add_argument("dir")
    r = sub.add_parser("turn", help="the clips turned about up")
    r.add_argument("dir")
    r.add_argument("out")
    r.add_argument("degrees", type=float)
    a = p.parse_args()
    if a.command == "table":
        table(a.dir)
    else:
        turn(a.dir, a.out, a.degrees)


if __name__ == "__main__":
    main()
