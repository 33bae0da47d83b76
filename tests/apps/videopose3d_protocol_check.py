#!/usr/bin/env python3
"""End-to-end check of the h36m and humaneva protocols on synthetic VideoPose3D files.

For each layout: write a synthetic npz in VideoPose3D's layout (tools/ --make-synthetic), convert
it, run `motionfork dataset stats --json`, and compare clip and window counts with an independent
reading of the npz that follows the published protocol (protocols.md; DLow's evaluation code):
subjects by split, the three bad HumanEva takes dropped, sequences shorter than t_his + t_pred
dropped, test windows range(0, T - (t_his + t_pred), t_his). Then the whole HumanEva-I chain a user
runs (README "Protocols"): `train` with a tiny config naming a prior that is not there yet (trained
first, on the same data), then `eval` of the bundle, whose report holds the model's figures beside
the published ones.

usage: videopose3d_protocol_check.py MOTIONFORK_BINARY SOURCE_DIR
"""
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

PROTOCOLS = {
    "h36m": dict(train=["S1", "S5", "S6", "S7", "S8"], test=["S9", "S11"], t_his=25, t_pred=100,
                 drop=set()),
    "humaneva": dict(train=["Train/S1", "Train/S2", "Train/S3"],
                     test=["Validate/S1", "Validate/S2", "Validate/S3"], t_his=15, t_pred=60,
                     drop={("Train/S3", "Walking 1 chunk0"), ("Train/S3", "Walking 1 chunk2"),
                           ("Validate/S3", "Walking 1 chunk4")}),
}


def expected(npz, p):
    data = np.load(npz, allow_pickle=True)["positions_3d"].item()
    total = p["t_his"] + p["t_pred"]
    out = {}
    for split in ("train", "test"):
        clips = usable = windows = 0
        for subject in p[split]:
            for action, seq in data.get(subject, {}).items():
                clips += 1
                if (subject, action) in p["drop"] or seq.shape[0] < total:
                    continue
                usable += 1
                windows += len(range(0, seq.shape[0] - total, p["t_his"]))
        out[split] = dict(clips=clips, usable=usable, test_windows=windows)
    return out


def check_published(binary, layout, data, tmp):
    """eval prints the protocol's published figures (GSPS, DLow, ...) beside the run's, and its
    JSON holds them; a run with K = 20 says it is not comparable."""
    failures = 0
    for k in (50, 20):
        report = os.path.join(tmp, "%s_eval_%d.json" % (layout, k))
        text = subprocess.run([binary, "--cache-dir", "none", "--quiet", "eval", "--baseline",
                               "zero-velocity", "--protocol", layout, "--data", data, "-k", str(k),
                               "--json", report], check=True, capture_output=True,
                              text=True).stdout
        with open(report) as f:
            got = json.load(f)
        methods = [p["method"] for p in got["published"]]
        differences = got["published_not_comparable_because"]
        ok = ("GSPS" in methods and "DLow" in methods and "published figures" in text and
              "this run leads on" in text and
              (differences == [] if k == 50 else differences == ["K = 20"]) and
              ("NOT comparable" in text) == (k != 50) and
              # zero-velocity's APD is 0: it never leads on diversity
              all("APD" not in p["this_run_leads_on"] for p in got["published"]))
        failures += not ok
        print("%s %-8s eval -k %d prints the published figures %s (not comparable: %s)" %
              ("ok  " if ok else "FAIL", layout, k, methods, differences))
    return failures


# configs/models/humaneva.yaml made tiny: the same protocol, constraints and losses, a network and
# an epoch small enough for seconds; the prior it names does not exist yet.
TINY_HUMANEVA = """name: tiny-humaneva
protocol: humaneva
constraints: humaneva
prior: %(prior)s
generator: {n_pre: 8, hidden: 16, blocks: 1, nz: 4, batch_norm: true, partition: default}
losses: {past_reconstruction: 100, limb_length: 500, diversity: [5, 10], diversity_scale: [15, 50],
         best_of_many: 2, multimodal: 1, prior_nll: 0.01, angle: 100}
multimodal: {last_pose_threshold: 0.05, future_min_distance: 0.1, max_per_window: 4}
training: {samples_per_part: [2, 2], batch_histories: 2, epochs: 2, windows_per_epoch: 8,
           lr_constant_epochs: 1, learning_rate: 0.001, grad_clip: 100, window_stride: 10,
           prior_frame_step: 3, seed: 0, threads: 1}
"""


def check_train_eval(binary, data, tmp):
    """train (prior first, then the generator) -> eval on the synthetic HumanEva-I folder."""
    prior, run = os.path.join(tmp, "prior-tiny"), os.path.join(tmp, "run-tiny")
    config = os.path.join(tmp, "tiny-humaneva.yaml")
    with open(config, "w") as f:
        f.write(TINY_HUMANEVA % dict(prior=prior))
    train = subprocess.run([binary, "--cache-dir", "none", "--quiet", "train", "--config", config,
                            "--data", data, "--out", run], capture_output=True, text=True)
    outputs = [train.stdout[-2000:], train.stderr[-2000:]]
    checks = [("train exits 0", train.returncode == 0),
              ("train says it trains the missing prior first",
               "not found: training it first" in train.stdout),
              ("the prior's schedule is raised to min_steps", "raised to reach" in train.stdout),
              ("the prior bundle is written", os.path.exists(os.path.join(prior, "prior.yaml"))),
              ("the generator bundle is written",
               all(os.path.exists(os.path.join(run, f)) for f in ("model.yaml", "generator.pt")))]
    if checks[0][1]:
        report = os.path.join(tmp, "tiny_eval.json")
        ev = subprocess.run([binary, "--cache-dir", "none", "--quiet", "eval", "--model", run,
                             "--protocol", "humaneva", "--data", data, "-k", "5", "--json", report],
                            capture_output=True, text=True)
        outputs += [ev.stdout[-3000:], ev.stderr[-2000:]]
        got = {}
        if ev.returncode == 0:
            with open(report) as f:
                got = json.load(f)
        checks += [("eval exits 0", ev.returncode == 0),
                   ("eval prints the published figures", "published figures" in ev.stdout),
                   ("eval's JSON holds the published rows",
                    any(p.get("method") == "GSPS" for p in got.get("published", []))),
                   ("eval says K = 5 is not comparable",
                    got.get("published_not_comparable_because") == ["K = 5"]),
                   ("eval's JSON names the trained bundle as the predictor",
                    got.get("predictor", {}).get("kind") == "model"),
                   ("eval's JSON holds the model's finite APD, ADE, FDE, MMADE, MMFDE",
                    all(isinstance(got.get(m), float) and math.isfinite(got[m]) and got[m] >= 0
                        for m in ("apd", "ade", "fde", "mmade", "mmfde")) and got["apd"] > 0)]
    failures = 0
    for what, ok in checks:
        failures += not ok
        print("%s humaneva train -> eval: %s" % ("ok  " if ok else "FAIL", what))
    if failures:
        print("\n".join(outputs))
    return failures


def main():
    binary, source = sys.argv[1], sys.argv[2]
    tool = os.path.join(source, "tools", "videopose3d_to_motionfork.py")
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for layout, p in PROTOCOLS.items():
            npz = os.path.join(tmp, layout + ".npz")
            out = os.path.join(tmp, layout)
            subprocess.run([sys.executable, tool, "--make-synthetic", npz, "--layout", layout],
                           check=True)
            subprocess.run([sys.executable, tool, npz, out], check=True, stdout=subprocess.DEVNULL)
            stats_json = os.path.join(tmp, layout + ".json")
            subprocess.run([binary, "--cache-dir", "none", "--quiet", "dataset", "stats",
                            "--protocol", layout, "--data", out, "--json", stats_json],
                           check=True, stdout=subprocess.DEVNULL)
            with open(stats_json) as f:
                got = json.load(f)
            want = expected(npz, p)
            for split in ("train", "test"):
                for key in ("clips", "usable", "test_windows"):
                    ok = got[split][key] == want[split][key]
                    failures += not ok
                    print("%s %-8s %-5s %-12s motionfork %6d  expected %6d  %s" %
                          ("ok  " if ok else "FAIL", layout, split, key, got[split][key],
                           want[split][key], "" if ok else "<--"))
            if want["test"]["test_windows"] == 0 or want["train"]["usable"] == 0:
                print("FAIL %s: the synthetic file gives no windows; the check proves nothing" % layout)
                failures += 1
            failures += check_published(binary, layout, out, tmp)
            if layout == "humaneva":
                failures += check_train_eval(binary, out, tmp)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
