#!/usr/bin/env python3
"""Benchmark: the Python module's predict() of a batch against the C++ API's same calls.

  PYTHONPATH=build/python python3 bench/python_api.py [--build build] [--batch 16] [-k 50]
                                                      [--rounds 5] [--repeats 5]

Both sides: the shipped models/bandai on one thread, B histories (a synthetic walk shifted by
1 mm per history, as bench_api_predict builds them), k futures each. The C++ side is
bench_api_predict --stdin, a process kept running that times one batch per request, so the two
alternate call by call (A/B interleaved: this machine's speed drifts by 30% over seconds, which
then affects both alike). Each round reports the median of its repeats of each; the ratio at the
end is over the medians of all calls.
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
        cpp = subprocess.Popen([bench, a.model, walk, "--batch", str(a.batch), "-k", str(a.k),
                                "--stdin"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               text=True)
        assert cpp.stdout.readline().strip() == "ready"
        all_py, all_cpp = [], []
        for r in range(a.rounds):
            py_ms, cpp_ms = [], []
            for _ in range(a.repeats):
                cpp.stdin.write("\n")
                cpp.stdin.flush()
                cpp_ms.append(float(cpp.stdout.readline()))
                t0 = time.perf_counter()
                model.predict(batch, k=a.k)
                py_ms.append(1000 * (time.perf_counter() - t0))
            all_py += py_ms
            all_cpp += cpp_ms
            py, c = statistics.median(py_ms), statistics.median(cpp_ms)
            print(f"round {r}: C++ API {c:.1f} ms, Python {py:.1f} ms ({py / c:.3f}x)")
        cpp.stdin.close()
        cpp.wait()
        py, c = statistics.median(all_py), statistics.median(all_cpp)
        print(f"batch {a.batch}, k {a.k}, {len(all_py)} calls each: C++ API median {c:.1f} ms, "
              f"Python median {py:.1f} ms, Python / C++ = {py / c:.3f}")


if __name__ == "__main__":
    main()
