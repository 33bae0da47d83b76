#!/usr/bin/env python3
"""Benchmark: the Python module's predict() of a batch against the C++ API's same calls.

  PYTHONPATH=build/python python3 bench/python_api.py [--build build] [--batch 16] [-k 50]
                                                      [--rounds 5] [--repeats 5]

Both sides: the shipped models/bandai on one thread, B histories (a synthetic walk shifted by
1 mm per history, as bench_api_predict builds them), k futures each. Rounds alternate the two
(A/B interleaved, so a CPU that changes speed affects both alike); each round reports the median
of its repeats. Prints both medians per round and the overall ratio Python / C++.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", default=os.path.join(root, "build"))
    p.add_argument("--model", default=os.path.join(root, "models", "bandai"))
    p.add_argument("--batch", type=int, default=16)
    p.add_argument("-k", type=int, default=50)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--repeats", type=int, default=5)
    a = p.parse_args()
    sys.path.insert(0, os.path.join(a.build, "python"))
    import motionfork as mf

    cli = os.path.join(a.build, "apps", "motionfork", "motionfork")
    bench = os.path.join(a.build, "bench", "bench_api_predict")
    with tempfile.TemporaryDirectory() as tmp:
        walk = os.path.join(tmp, "walk.bvh")
        subprocess.run([cli, "--quiet", "synth", "walk", "--frames", "30", "-o", walk], check=True)
        model = mf.Model.load(a.model, threads=1)
        history = model.read_motion(walk)
        batch = np.stack([history + np.float32(0.001) * b for b in range(a.batch)])
        model.predict(batch, k=a.k)  # warm-up
        py_ms, cpp_ms = [], []
        for r in range(a.rounds):
            out = subprocess.run([bench, a.model, walk, "--batch", str(a.batch), "-k", str(a.k),
                                  "--repeats", str(a.repeats)], check=True, capture_output=True,
                                 text=True).stdout
            cpp_ms.append(float(out.split("median_ms")[1]))
            times = []
            for _ in range(a.repeats):
                t0 = time.perf_counter()
                model.predict(batch, k=a.k)
                times.append(1000 * (time.perf_counter() - t0))
            py_ms.append(statistics.median(times))
            print(f"round {r}: C++ API {cpp_ms[-1]:.1f} ms, Python {py_ms[-1]:.1f} ms "
                  f"({py_ms[-1] / cpp_ms[-1]:.3f}x)")
        ratio = statistics.median(py_ms) / statistics.median(cpp_ms)
        print(f"batch {a.batch}, k {a.k}: C++ API median {statistics.median(cpp_ms):.1f} ms, "
              f"Python median {statistics.median(py_ms):.1f} ms, Python / C++ = {ratio:.3f}")


if __name__ == "__main__":
    main()
