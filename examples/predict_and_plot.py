#!/usr/bin/env python3
"""From Python: predict futures of a walk, check them, and plot them with matplotlib.

  PYTHONPATH=build/python python3 examples/predict_and_plot.py [HISTORY] [--out futures.png]

HISTORY: a .bvh, .npy or .csv motion (default: a synthetic walk from `motionfork synth walk`).
Run it cell by cell in a notebook as well: each block below is one step.
"""
import argparse
import os
import subprocess
import tempfile

import matplotlib

matplotlib.use("Agg")  # files, no window; drop this line in a notebook
import matplotlib.pyplot as plt
import numpy as np

import motionfork as mf

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

p = argparse.ArgumentParser(description="Predict, check and plot futures of a motion.")
p.add_argument("history", nargs="?", help="motion file (default: a synthetic walk)")
p.add_argument("--model", default=os.path.join(ROOT, "models", "bandai"))
p.add_argument("--out", default="futures.png")
p.add_argument("-k", type=int, default=20)
args = p.parse_args()

# 1. A history: your file, or a walk the command synthesises.
path = args.history
if path is None:
    path = os.path.join(tempfile.mkdtemp(), "walk.bvh")
    subprocess.run([os.path.join(ROOT, "build", "apps", "motionfork", "motionfork"), "--quiet",
                    "synth", "walk", "-o", path], check=True)

# 2. The model, and the history on its joints (mapped by name, resampled to its frame rate).
model = mf.Model.load(args.model)
history = model.read_motion(path)
print(f"{path}: {history.shape[0]} frames of {len(model.joint_names)} joints at {model.fps} Hz")

# 3. k futures; then k more with the legs shared by all (same legs, varied upper body).
futures = model.predict(history, k=args.k, seed=0)
same_legs = model.predict(history, k=args.k, seed=0, fix=["legs"])
print("futures:", futures.shape, "(k, history + future frames, joints, xyz)")

# 4. Every future against the angle ranges and the pose prior.
checks = model.check(futures[:, model.history_frames:])
valid = sum(c["valid"] for c in checks)
print(f"valid futures: {valid} of {len(checks)}; mean prior NLL "
      f"{np.mean([c['nll'] for c in checks]):.1f} nats per pose")

# 5. Plot the left hand's and left foot's height over time for both sets: with the legs fixed the
# foot curves coincide while the hands still vary. Invalid futures in red.
hand, foot = model.joint_names.index("Hand_L"), model.joint_names.index("Foot_L")
t = (np.arange(futures.shape[1]) - model.history_frames + 1) / model.fps  # seconds, 0 = now
fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
for ax, set_, title in ((axes[0], futures, "free"), (axes[1], same_legs, "legs fixed")):
    set_checks = model.check(set_[:, model.history_frames:])
    for sample, check in zip(set_, set_checks):
        ax.plot(t, sample[:, hand, 1], color="tab:blue" if check["valid"] else "tab:red",
                alpha=0.4, lw=1)
        ax.plot(t, sample[:, foot, 1], color="tab:green" if check["valid"] else "tab:red",
                alpha=0.4, lw=1)
    h = slice(0, model.history_frames)
    ax.plot(t[h], set_[0, h, hand, 1], color="black", lw=2, label="history")
    ax.plot(t[h], set_[0, h, foot, 1], color="black", lw=2)
    ax.axvline(0, color="grey", lw=0.5)
    ax.set_title(f"{title}: left hand (blue) and foot (green), {len(set_)} futures")
    ax.set_xlabel("time from the last history frame (s)")
axes[0].set_ylabel("height (m)")
axes[0].legend()
fig.tight_layout()
fig.savefig(args.out, dpi=100)
print("wrote", args.out)
