#!/usr/bin/env python3
"""Convert VideoPose3D's 3D pose exports into motionfork's plain layout.

Input: data_3d_h36m.npz or data_3d_humaneva15.npz as written by VideoPose3D's prepare_data_*.py:
the key 'positions_3d' holds a pickled dict subject -> action -> float32 [T, J, 3] (metres).

Output (read by motionfork's ReadVideoPose3dManifest):
    OUTDIR/<subject>/<action>.npy   float32 [T, J, 3], C order, metres, values as stored in the npz
    OUTDIR/manifest.tsv             subject<TAB>action<TAB>frames<TAB>joints<TAB>fps<TAB>file
                                    one row per take; file is relative to OUTDIR, '/'-separated

A subject such as 'Train/S1' becomes nested folders. The manifest is written last, through a
temporary file and a rename, and any old manifest is removed first: a folder with a manifest.tsv
is always a complete conversion.

Needs only Python 3 and numpy. Loading the npz unpickles it (allow_pickle=True): only convert
files you trust, as VideoPose3D itself does.

Exit codes: 0 success, 2 bad usage or invalid input (nothing written), 1 a write failed.

--make-synthetic OUT.npz --layout h36m|humaneva writes a small synthetic file in exactly
VideoPose3D's layout (deterministic for --seed), for tests that must run without the licensed data.
"""

import argparse
import os
import sys
import tempfile

try:
    import numpy as np
except ImportError:  # pragma: no cover - depends on the machine
    sys.stderr.write("error: this tool needs numpy (Debian: apt-get install python3-numpy)\n")
    sys.exit(2)

MANIFEST = "manifest.tsv"
MANIFEST_HEADER = ["subject", "action", "frames", "joints", "fps", "file"]
# Frame rates of the two VideoPose3D exports, keyed by joint count (protocols.md).
DEFAULT_FPS = {32: 50.0, 15: 60.0}

# Parents of the skeletons in the exports (protocols.md), used to make plausible synthetic bodies.
H36M_PARENTS = [-1, 0, 1, 2, 3, 4, 0, 6, 7, 8, 9, 0, 11, 12, 13, 14, 12, 16, 17, 18, 19, 20, 19,
                22, 12, 24, 25, 26, 27, 28, 27, 30]
HUMANEVA_PARENTS = [-1, 0, 1, 2, 3, 1, 5, 6, 0, 8, 9, 0, 11, 12, 1]


UMASK = os.umask(0)
os.umask(UMASK)


class InputError(Exception):
    """Invalid input: reported with exit code 2 before anything is written."""


# ---------------------------------------------------------------------------------------------
# Conversion


def load_positions(path):
    """Returns the dict subject -> action -> array from a VideoPose3D npz, or raises InputError."""
    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file")
    try:
        npz = np.load(path, allow_pickle=True)
    except Exception as e:  # numpy raises several types for a non-npz file
        raise InputError(f"{path}: cannot read as a .npz file ({type(e).__name__}: {e})")
    if not hasattr(npz, "files"):
        raise InputError(f"{path}: expected a .npz archive, found a single array (.npy)")
    with npz:
        if "positions_3d" not in npz.files:
            raise InputError(
                f"{path}: expected the key 'positions_3d' (VideoPose3D's data_3d_*.npz), "
                f"found keys {sorted(npz.files)}")
        try:
            positions = npz["positions_3d"].item()
        except Exception as e:
            raise InputError(
                f"{path}: expected 'positions_3d' to hold a pickled dict, cannot read it "
                f"({type(e).__name__}: {e})")
    if not isinstance(positions, dict):
        raise InputError(
            f"{path}: expected 'positions_3d' to hold a dict subject -> action -> array, "
            f"found {type(positions).__name__}")
    if not positions:
        raise InputError(f"{path}: 'positions_3d' holds no subjects")
    return positions


def check_name(kind, name, allow_slash):
    """Subjects and actions become paths and TSV fields: refuse what would break either."""
    if not isinstance(name, str) or not name:
        raise InputError(f"expected a non-empty string as {kind} name, found {name!r}")
    if any(c in name for c in "\t\n\r\0\\"):
        raise InputError(f"{kind} name {name!r} contains a tab, line break, NUL or backslash")
    parts = name.split("/")
    if not allow_slash and len(parts) > 1:
        raise InputError(f"{kind} name {name!r} contains '/'")
    if any(p in ("", ".", "..") for p in parts):
        raise InputError(f"{kind} name {name!r} has an empty, '.' or '..' path component")
    if parts[0] == MANIFEST:
        raise InputError(f"{kind} name {name!r} would overwrite {MANIFEST}")


def validate(positions, fps_override):
    """Checks every take; returns a sorted list of (subject, action, float32 array, fps)."""
    takes = []
    for subject in sorted(positions, key=str):
        check_name("subject", subject, allow_slash=True)
        actions = positions[subject]
        if not isinstance(actions, dict):
            raise InputError(f"subject {subject!r}: expected a dict action -> array, "
                             f"found {type(actions).__name__}")
        for action in sorted(actions, key=str):
            check_name("action", action, allow_slash=False)
            where = f"subject {subject!r}, action {action!r}"
            a = actions[action]
            if not isinstance(a, np.ndarray):
                raise InputError(f"{where}: expected a numpy array, found {type(a).__name__}")
            if a.dtype.kind != "f":
                raise InputError(f"{where}: expected a float array, found dtype {a.dtype}")
            if a.ndim != 3 or a.shape[2] != 3 or a.shape[0] < 1 or a.shape[1] < 1:
                raise InputError(f"{where}: expected shape [T, J, 3] with T, J >= 1, "
                                 f"found {list(a.shape)}")
            a32 = np.ascontiguousarray(a, dtype="<f4")
            bad = ~np.isfinite(a32)
            if bad.any():
                t, j, c = (int(i) for i in np.argwhere(bad)[0])
                raise InputError(f"{where}: non-finite value {a32[t, j, c]} at frame {t}, "
                                 f"joint {j}, coordinate {'xyz'[c]} ({int(bad.sum())} in all)")
            joints = a.shape[1]
            if fps_override is not None:
                fps = fps_override
            elif joints in DEFAULT_FPS:
                fps = DEFAULT_FPS[joints]
            else:
                raise InputError(f"{where}: {joints} joints is neither H36M (32, 50 Hz) nor "
                                 f"HumanEva-I (15, 60 Hz); give the frame rate with --fps")
            takes.append((subject, action, a32, fps))
    if not takes:
        raise InputError("the input holds no takes")
    return takes


def write_atomically(path, write):
    """Calls write(file_object) on a temporary file next to path, then renames it into place."""
    folder = os.path.dirname(path) or "."
    fd, tmp = tempfile.mkstemp(prefix=".tmp_", dir=folder)
    try:
        os.chmod(tmp, 0o666 & ~UMASK)  # mkstemp makes 0600 files; give them the usual mode
        with os.fdopen(fd, "wb") as f:
            write(f)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def format_fps(fps):
    return f"{fps:g}" if float(fps).is_integer() else repr(float(fps))


def convert(input_path, outdir, fps_override):
    takes = validate(load_positions(input_path), fps_override)
    os.makedirs(outdir, exist_ok=True)
    manifest = os.path.join(outdir, MANIFEST)
    # An old manifest would describe files this run is about to replace.
    if os.path.lexists(manifest):
        os.unlink(manifest)
    rows = ["\t".join(MANIFEST_HEADER)]
    for subject, action, a32, fps in takes:
        rel = subject + "/" + action + ".npy"
        path = os.path.join(outdir, *rel.split("/"))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_atomically(path, lambda f, a=a32: np.save(f, a, allow_pickle=False))
        rows.append("\t".join([subject, action, str(a32.shape[0]), str(a32.shape[1]),
                               format_fps(fps), rel]))
    text = "\n".join(rows) + "\n"
    write_atomically(manifest, lambda f: f.write(text.encode("utf-8")))
    return len(takes)


# ---------------------------------------------------------------------------------------------
# Synthetic data in VideoPose3D's layout

H36M_SUBJECTS = ["S1", "S5", "S6", "S7", "S8", "S9", "S11"]
H36M_ACTIONS = ["Directions", "Walking", "Walking 1"]
HUMANEVA_SUBJECTS = ["Train/S1", "Train/S2", "Train/S3", "Validate/S1", "Validate/S2",
                     "Validate/S3"]
# Includes the three takes the protocol drops (Train/S3 Walking 1 chunk0 and chunk2,
# Validate/S3 Walking 1 chunk4): every subject has Walking 1 chunk0..chunk4.
HUMANEVA_ACTIONS = ["Walking 1 chunk0", "Walking 1 chunk1", "Walking 1 chunk2",
                    "Walking 1 chunk3", "Walking 1 chunk4", "Jog 1 chunk0", "Box 1 chunk0"]
# Frame counts are drawn uniformly from [low, high): some takes are shorter than a protocol
# window (H36M 25 + 100 = 125 frames, HumanEva 15 + 60 = 75), most are longer.
LAYOUTS = {
    "h36m": dict(subjects=H36M_SUBJECTS, actions=H36M_ACTIONS, parents=H36M_PARENTS,
                 fps=50.0, frames=(100, 260)),
    "humaneva": dict(subjects=HUMANEVA_SUBJECTS, actions=HUMANEVA_ACTIONS,
                     parents=HUMANEVA_PARENTS, fps=60.0, frames=(50, 200)),
}


def synthetic_take(rng, parents, frames, fps):
    """A smooth [frames, J, 3] float32 motion: bones of random direction and length 5-45 cm
    wobbling around a rest pose, the root walking forward. Metres, Y up."""
    joints = len(parents)
    direction = rng.normal(size=(joints, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    offsets = direction * rng.uniform(0.05, 0.45, size=(joints, 1))
    offsets[0] = [0.0, 0.95, 0.0]
    phase = rng.uniform(0, 2 * np.pi, size=(joints, 3))
    speed = rng.uniform(0.5, 2.0, size=(joints, 1))
    t = np.arange(frames, dtype=np.float64)[:, None, None] / fps
    local = offsets[None] + 0.05 * np.sin(2 * np.pi * speed[None] * t + phase[None])
    local[:, 0, 0] += rng.uniform(-1, 1) * t[:, 0, 0]  # root drift along X and Z
    local[:, 0, 2] += rng.uniform(0.5, 1.5) * t[:, 0, 0]
    world = np.empty_like(local)
    for j, p in enumerate(parents):
        world[:, j] = local[:, j] if p < 0 else world[:, p] + local[:, j]
    return world.astype(np.float32)


def make_synthetic(out_path, layout, seed):
    spec = LAYOUTS[layout]
    rng = np.random.RandomState(seed)  # legacy generator: stable across numpy versions
    positions = {}
    for subject in spec["subjects"]:
        positions[subject] = {}
        for action in spec["actions"]:
            frames = int(rng.randint(*spec["frames"]))
            positions[subject][action] = synthetic_take(rng, spec["parents"], frames, spec["fps"])
    folder = os.path.dirname(os.path.abspath(out_path))
    os.makedirs(folder, exist_ok=True)
    # What VideoPose3D's prepare_data_*.py does: np.savez_compressed(out, positions_3d=dict).
    write_atomically(out_path, lambda f: np.savez_compressed(f, positions_3d=positions))
    return sum(len(a) for a in positions.values())


# ---------------------------------------------------------------------------------------------


def parse_args(argv):
    p = argparse.ArgumentParser(
        description="Convert VideoPose3D's data_3d_h36m.npz / data_3d_humaneva15.npz into "
                    "OUTDIR/<subject>/<action>.npy plus OUTDIR/manifest.tsv for motionfork.",
        epilog="Exit codes: 0 success, 2 bad usage or invalid input, 1 write failure.")
    p.add_argument("input", nargs="?", metavar="INPUT.npz", help="VideoPose3D 3D positions file")
    p.add_argument("outdir", nargs="?", metavar="OUTDIR", help="output folder (created)")
    p.add_argument("--fps", type=float, default=None,
                   help="frame rate in Hz written to the manifest (default: 50 for 32 joints "
                        "(Human3.6M), 60 for 15 joints (HumanEva-I); required otherwise)")
    p.add_argument("--make-synthetic", metavar="OUT.npz", default=None,
                   help="instead of converting, write a small synthetic npz in VideoPose3D's "
                        "layout")
    p.add_argument("--layout", choices=sorted(LAYOUTS), default=None,
                   help="layout of the synthetic file (with --make-synthetic)")
    p.add_argument("--seed", type=int, default=0,
                   help="seed of the synthetic take lengths and motion (default 0)")
    args = p.parse_args(argv)
    if args.make_synthetic is not None:
        if args.layout is None:
            p.error("--make-synthetic needs --layout h36m or --layout humaneva")
        if args.input is not None:
            p.error("--make-synthetic takes no INPUT/OUTDIR")
        if args.seed < 0:
            p.error("--seed must be >= 0")
    else:
        if args.input is None or args.outdir is None:
            p.error("expected INPUT.npz and OUTDIR (or --make-synthetic OUT.npz --layout ...)")
        if args.layout is not None:
            p.error("--layout goes with --make-synthetic")
        if args.fps is not None and not (args.fps > 0 and np.isfinite(args.fps)):
            p.error(f"--fps must be a number > 0, got {args.fps}")
    return args


def main(argv=None):
    args = parse_args(argv)
    try:
        if args.make_synthetic is not None:
            n = make_synthetic(args.make_synthetic, args.layout, args.seed)
            print(f"wrote {n} synthetic {args.layout} takes to {args.make_synthetic}")
        else:
            n = convert(args.input, args.outdir, args.fps)
            print(f"wrote {n} takes and {MANIFEST} to {args.outdir}")
    except InputError as e:
        sys.stderr.write(f"error: {e}\n")
        return 2
    except OSError as e:
        sys.stderr.write(f"error: cannot write: {e}\n")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
