"""tools/headings.py: the heading table counts the sectors the hips face, and turning the clips
by 90 degrees moves every frame one quarter round; a non-empty output folder is refused.

    python3 tests/tools/headings_check.py tools/headings.py
"""

import math
import os
import subprocess
import sys
import tempfile

JOINTS = ["Hips", "UpperLeg_R", "UpperLeg_L"]


def write_clip(path, heading_deg, frames=30):
    """A body whose hip line (right to left) points at heading_deg on the ground (atan2(x, z))."""
    h = math.radians(heading_deg)
    with open(path, "w") as f:
        f.write("# motionfork positions; fps=30; unit=m; skeleton=test\n")
        f.write(",".join(f"{j}.{a}" for j in JOINTS for a in "xyz") + "\n")
        for t in range(frames):
            lx, lz = 0.1 * math.sin(h), 0.1 * math.cos(h)
            row = [0.01 * t, 1.0, 0.0, -lx, 0.9, -lz, lx, 0.9, lz]
            f.write(",".join(f"{v:.6f}" for v in row) + "\n")


def table(tool, folder):
    out = subprocess.run([sys.executable, tool, "table", folder], capture_output=True, text=True,
                         check=True).stdout.splitlines()
    sectors = [int(s) for s in out[0].split()[1:]]
    return {line.split()[0]: dict(zip(sectors, map(int, line.split()[1:]))) for line in out[1:]}


def main():
    tool = sys.argv[1]
    with tempfile.TemporaryDirectory() as d:
        clips = os.path.join(d, "clips")
        os.makedirs(clips)
        write_clip(os.path.join(clips, "dataset-2_wave_normal_001.csv"), 90)
        write_clip(os.path.join(clips, "dataset-2_walk_normal_001.csv"), -88)
        t = table(tool, clips)
        # Frames 14 of 30 only (every 15th from 14: 14, 29): two a clip.
        assert t["wave"][90] == 2 and sum(t["wave"].values()) == 2, t
        assert t["walk"][-90] == 2 and sum(t["walk"].values()) == 2, t
        turned = os.path.join(d, "turned")
        subprocess.run([sys.executable, tool, "turn", clips, turned, "90"], check=True)
        t = table(tool, turned)
        # Every heading grows by 90 degrees: 90 -> 180 (the sector of -180), -88 -> 2.
        assert t["wave"][-180] == 2 and t["walk"][0] == 2, t
        r = subprocess.run([sys.executable, tool, "turn", clips, turned, "90"],
                           capture_output=True, text=True)
        assert r.returncode != 0 and "not empty" in r.stderr, r.stderr
    print("headings: table and turn as expected")


if __name__ == "__main__":
    main()
