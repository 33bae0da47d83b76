"""Check that Blender reads a motionfork BVH file as the joint positions motionfork wrote.

Run headless with Blender (Debian's `blender` package):

  blender -b --factory-startup --python tools/blender_check_bvh.py -- FILE.bvh POSITIONS [options]

POSITIONS is the motion to compare with, in metres:
  .csv  motionfork's CSV (one row per frame, columns "Joint.x,Joint.y,Joint.z"): joints matched
        to Blender's bones by name, e.g. the file the BVH was converted from
        (`motionfork convert IN.csv OUT.bvh` keeps positions), or the BVH's own positions as
        motionfork reads them (`motionfork convert OUT.bvh OUT.csv`);
  .npy  float32/float64 [T, J, 3] in the BVH file's joint order (needs numpy in Blender's Python).

The file is imported with Blender's own importer (File > Import > Motion Capture), with its
axis options given explicitly: BVH is Y-up, Blender Z-up, so the importer turns the armature by
axis_conversion(forward='-Z', up='Y'); this script applies the inverse to every bone head, and
imports with global_scale = the file's unit in metres (--scale, 0.01 for the centimetres
motionfork writes by default) so the heads come out in metres. It then steps through the frames
(BVH frame t is Blender frame 1 + t) and compares each pose bone's head in world space with the
joint's position.

Prints the largest error (mm, with its frame and joint) and exits 0 when it is within
--tolerance-mm (default 1), 1 when it is not, 2 on bad input (missing joint, frame count).
"""

import argparse
import csv
import sys

import bpy
from bpy_extras.io_utils import axis_conversion
from mathutils import Vector


def fail(message, code=2):
    print("blender_check_bvh: error: " + message, file=sys.stderr)
    sys.stdout.flush()
    sys.exit(code)


def read_csv(path):
    """Joint names and frames [T][J] of (x, y, z) metres from a motionfork CSV."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        fail(f"{path}: no header line; expected 'Joint.x,Joint.y,Joint.z,...'")
    header = [h.strip() for h in rows[0]]
    if len(header) % 3 != 0:
        fail(f"{path}: header has {len(header)} columns; expected 3 per joint")
    names = []
    for j in range(0, len(header), 3):
        base = header[j][:-2]
        if [header[j], header[j + 1], header[j + 2]] != [base + ".x", base + ".y", base + ".z"]:
            fail(f"{path}: columns {j + 1}-{j + 3} are {header[j:j + 3]}; expected NAME.x, NAME.y, NAME.z")
        names.append(base)
    frames = []
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            fail(f"{path}: row {line} has {len(row)} values; expected {len(header)}")
        v = [float(x) for x in row]
        frames.append([(v[3 * j], v[3 * j + 1], v[3 * j + 2]) for j in range(len(names))])
    return names, frames


def read_npy(path, bone_names):
    import numpy as np

    a = np.load(path)
    if a.ndim != 3 or a.shape[2] != 3 or a.shape[1] != len(bone_names):
        fail(f"{path}: shape {a.shape}; expected [T, {len(bone_names)}, 3] (the BVH's joints)")
    return list(bone_names), [[tuple(map(float, p)) for p in frame] for frame in a]


def allow_universal_newline_mode():
    """Debian's Blender 3.4 runs Python 3.11, which dropped open()'s 'U' mode, but its BVH importer
    still opens files with mode 'rU' (ValueError: invalid mode). Give the importer's module an
    open() that drops the 'U' (universal newlines are the default in Python 3 anyway)."""
    import builtins

    import io_anim_bvh.import_bvh as importer

    def open_without_u(file, mode="r", *args, **kwargs):
        return builtins.open(file, mode.replace("U", ""), *args, **kwargs)

    importer.open = open_without_u


def bvh_frame_count(path):
    with open(path) as f:
        for line in f:
            words = line.split()
            if len(words) == 2 and words[0].lower() == "frames:":
                return int(words[1])
    fail(f"{path}: no 'Frames:' line")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(
        prog="blender -b --factory-startup --python tools/blender_check_bvh.py --",
        description="Compare Blender's import of a BVH file with joint positions (metres).")
    ap.add_argument("bvh", help="BVH file written by motionfork")
    ap.add_argument("positions", help="positions to compare with: motionfork .csv or .npy [T, J, 3], metres")
    ap.add_argument("--scale", type=float, default=0.01,
                    help="BVH length unit in metres (default 0.01: centimetres, motionfork's default)")
    ap.add_argument("--tolerance-mm", type=float, default=1.0, help="largest allowed error, mm (default 1)")
    args = ap.parse_args(argv)

    allow_universal_newline_mode()
    # Y-up BVH into Z-up Blender; the same matrix the importer builds from these options.
    bpy.ops.import_anim.bvh(filepath=args.bvh, target='ARMATURE', global_scale=args.scale,
                            frame_start=1, use_fps_scale=False, update_scene_fps=False,
                            update_scene_duration=True, rotate_mode='NATIVE',
                            axis_forward='-Z', axis_up='Y')
    to_file = axis_conversion(from_forward='-Z', from_up='Y').to_4x4().inverted()
    armatures = [o for o in bpy.context.scene.objects if o.type == 'ARMATURE']
    if len(armatures) != 1:
        fail(f"{args.bvh}: expected one armature after the import, found {len(armatures)}")
    arm = armatures[0]
    bones = arm.pose.bones

    if args.positions.lower().endswith(".npy"):
        names, frames = read_npy(args.positions, [b.name for b in bones])
    else:
        names, frames = read_csv(args.positions)
    missing = [n for n in names if n not in bones]
    if missing:
        fail(f"{args.bvh}: joints {missing} of {args.positions} are not bones of the imported armature "
             f"(bones: {[b.name for b in bones]})")
    frame_count = bvh_frame_count(args.bvh)
    if frame_count != len(frames):
        fail(f"{args.bvh} has {frame_count} frames, {args.positions} {len(frames)}; expected the same")

    scene = bpy.context.scene
    worst, where = 0.0, "no frames"
    for t, frame in enumerate(frames):
        scene.frame_set(1 + t)
        for name, p in zip(names, frame):
            head = to_file @ (arm.matrix_world @ bones[name].head)
            err = (head - Vector(p)).length
            if err > worst:
                worst, where = err, f"frame {t}, joint '{name}'"
    print(f"blender_check_bvh: {args.bvh}: {len(frames)} frames, {len(names)} joints; "
          f"max error {worst * 1000:.6f} mm ({where}); tolerance {args.tolerance_mm} mm")
    sys.stdout.flush()
    sys.exit(0 if worst * 1000 <= args.tolerance_mm else 1)


main()
