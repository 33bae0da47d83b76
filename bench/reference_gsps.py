#!/usr/bin/env python3
"""Reference timing: the original GSPS generator's inference in plain PyTorch eager mode (issue 30).

  taskset -c 1 /usr/bin/python3 bench/reference_gsps.py [--threads 1] [--rounds 7] [--warmup 3]
  /usr/bin/python3 bench/reference_gsps.py --serve [--threads 1]

The "reference PyTorch code" our C++ generator is compared with: GSPS (ICCV 2021, "Generating
Smooth Pose Sequences for Diverse Human Motion Prediction") as its released code runs a trained
generator, float32, eval mode, no autograd, on the CPU, `--threads` intra-op threads (default 1).
Needs only PyTorch (Debian: apt-get install python3-torch); installs nothing. The weights are
random (seed 0; batch norm at its initial running statistics): the time does not depend on them.

Sizes: Human3.6M's, as bench/generator_sizes.h: 16 nodes (17 joints less the root), t_his 25,
t_pred 100, n_pre 10 DCT coefficients, hidden 256, 4 residual blocks, nz 64, two parts predicted
in sequence: nodes 0..5 (legs), then 6..15 (upper body).

One run = 50 futures of one history, as bench_generator's "50 futures of 1 history": the history
[1, t_his, 16, 3] (random, drawn once) -> padded to t_his + t_pred frames with its last frame ->
DCT (orthonormal DCT-II, first n_pre rows, one matmul) -> coefficients repeated 50 times ->
latents drawn -> part 1's network -> part 2's network -> inverse DCT to t_his + t_pred frames
[50, 125, 16, 3]. Timed with time.perf_counter (the latent draw included, the history not, as in
bench_generator). Standalone: --warmup runs, then --rounds runs; prints the median and each run.
--serve, for A/B interleaving from C++: builds and warms up, prints "ready <parameters>", then
reads stdin line by line: "run" -> one run, prints its ms with 4 decimals; "quit" or EOF -> exits
(anything else: a message on stderr, exit status 2). Every reply is flushed.

What this follows of the released GSPS code (github.com/wei-mao-2019/gsps, models/GCN.py,
models/motion_pred_ours.py, eval.py, utils/util.py, motion_pred/cfg/h36m.yml), rewritten here,
not copied:
- Layout batch-major [samples, nodes, features]. A graph-conv is two torch.matmul calls, the
  features product X W and then the learned dense node-by-node matrix on the left, broadcast over
  the batch, plus a bias; all of a layer's parameters start uniform in +-1/sqrt(out features).
- Each batch-normalised layer views its [B, nodes, features] output as [B, nodes * features] and
  runs a BatchNorm1d over that, then tanh (an nn module, not folded into anything). Dropout is
  not in the code (commented out there), so there is none here either.
- A part's network: input graph-conv (with bias) + batch norm + tanh; 4 residual blocks, each two
  graph-convs *without* bias (the batch norm after them has its own shift) + batch norm + tanh,
  plus the block input; an output graph-conv (with bias) back to the network's *full* input width,
  coefficients and latent, plus the whole input.
- The latent is joined to the graph as data: each part's z is repeated to every node and
  concatenated to the current coefficients, so the input layer's product is 94 features wide
  (30 coefficients + 64), and the output layer produces 94 features of which the first 30 are
  kept. Parts run in order on a clone of the coefficients; part i's network sees the whole graph
  (with earlier parts' results) and its result is written back into part i's nodes only by
  indexing with the node list.
- Sampling (its eval script): DCT of the one history first, then the coefficients repeated K
  times in the batch dimension (not the frames); the latents of all parts drawn as one
  standard-normal tensor [K, parts, nz]; eval mode; no autograd. The DCT matrix is built in
  float64, its inverse as the matrix inverse, both cast to float32; padding is an index gather
  over the time axis; coefficients per node are [x coefficients, y's, z's] as in our C++.
- Not timed here, although the released eval script does them per call: rebuilding the
  125 x 125 DCT matrix in a Python loop (tens of ms), NumPy <-> tensor conversion, slicing off the
  history and concatenating the input history to the futures. They are not the generator.

Parameters: 1,298,108 (649,054 per part; checked below against the formula and against the
spec's "about 1.3M for H36M, two parts"). Our C++ GeneratorNet (src/generator/model/gcn.cc) has
1,269,308 (634,654 per part), 28,800 fewer: its output graph-conv maps 256 -> 30 coefficients
only (GSPS: 256 -> 94, i.e. 2 x (256 x 64 weights + 64 biases) = 32,896 more here), and its
input layer's latent weight (64 x 256) is the same count as GSPS's 94-wide weight rows; but every
C++ graph-conv has a bias, the 8 per part inside the residual blocks included (2 x 8 x 256 =
4,096 more there). 32,896 - 4,096 = 28,800. The work differs likewise: per sample GSPS multiplies
all 16 nodes' 64 latent features in the input layer (C++: one 64 x 256 product per sample, added
to every node) and computes 64 output features per node it then discards; C++'s LibTorch network
runs node-major [nodes, samples, features] with one node-mixing product per layer, adds the conv
bias, and applies batch norm as a per-call scale and shift fused with tanh (FusedGenerator folds
it into a fixed scale and shift per node and feature); here BatchNorm1d and tanh are separate ops.
"""
import argparse
import statistics
import sys
import time

import torch
from torch import nn

T_HIS, T_PRED, N_PRE, HIDDEN, BLOCKS, NZ, NODES = 25, 100, 10, 256, 4, 64, 16
PARTS = [[0, 1, 2, 3, 4, 5], [6, 7, 8, 9, 10, 11, 12, 13, 14, 15]]


class GraphConv(nn.Module):
    """Y = A (X W) [+ b] on [batch, nodes, features], A a learned dense [nodes, nodes] matrix."""

    def __init__(self, nodes, fin, fout, bias):
        super().__init__()
        bound = fout ** -0.5
        self.weight = nn.Parameter(torch.empty(fin, fout).uniform_(-bound, bound))
        self.adjacency = nn.Parameter(torch.empty(nodes, nodes).uniform_(-bound, bound))
        self.bias = nn.Parameter(torch.empty(fout).uniform_(-bound, bound)) if bias else None

    def forward(self, x):
        y = torch.matmul(self.adjacency, torch.matmul(x, self.weight))
        return y if self.bias is None else y + self.bias


class NormedLayer(nn.Module):
    """Graph-conv, batch norm over nodes x features (BatchNorm1d on the flattened node axis), tanh."""

    def __init__(self, nodes, fin, fout, bias):
        super().__init__()
        self.conv = GraphConv(nodes, fin, fout, bias)
        self.norm = nn.BatchNorm1d(nodes * fout)
        self.act = nn.Tanh()

    def forward(self, x):
        y = self.conv(x)
        b, n, f = y.shape
        return self.act(self.norm(y.view(b, n * f)).view(b, n, f))


class ResidualBlock(nn.Module):
    def __init__(self, nodes, width):
        super().__init__()
        self.first = NormedLayer(nodes, width, width, bias=False)
        self.second = NormedLayer(nodes, width, width, bias=False)

    def forward(self, x):
        return self.second(self.first(x)) + x


class PartNetwork(nn.Module):
    """Input layer, residual blocks, output graph-conv back to the input width, plus the input."""

    def __init__(self, nodes, width_in, hidden, blocks):
        super().__init__()
        self.head = NormedLayer(nodes, width_in, hidden, bias=True)
        self.body = nn.Sequential(*[ResidualBlock(nodes, hidden) for _ in range(blocks)])
        self.tail = GraphConv(nodes, hidden, width_in, bias=True)

    def forward(self, x):
        return self.tail(self.body(self.head(x))) + x


def dct_matrices(frames, keep):
    """Orthonormal DCT-II rows [keep, frames] and the inverse's columns [frames, keep], float32."""
    t = torch.arange(frames, dtype=torch.float64)
    k = t.unsqueeze(1)
    d = torch.cos(torch.pi * (t + 0.5) * k / frames) * (2.0 / frames) ** 0.5
    d[0] *= 0.5 ** 0.5
    inverse = torch.linalg.inv(d)
    return d[:keep].float().contiguous(), inverse[:, :keep].float().contiguous()


class Generator(nn.Module):
    def __init__(self):
        super().__init__()
        self.coeffs = 3 * N_PRE
        self.nets = nn.ModuleList(
            [PartNetwork(NODES, self.coeffs + NZ, HIDDEN, BLOCKS) for _ in PARTS])
        dct, idct = dct_matrices(T_HIS + T_PRED, N_PRE)
        self.register_buffer("dct", dct)
        self.register_buffer("idct", idct)
        self.register_buffer("pad", torch.tensor(list(range(T_HIS)) + [T_HIS - 1] * T_PRED))

    def forward(self, history, z):
        """history [Bh, t_his, N, 3], z [Bh * K, parts, nz] -> frames [Bh * K, t_his + t_pred, N, 3]."""
        bh = history.shape[0]
        k = z.shape[0] // bh
        padded = history.reshape(bh, T_HIS, NODES * 3)[:, self.pad]  # [Bh, T, 3N]
        c = torch.matmul(self.dct, padded)  # [Bh, n_pre, 3N]
        c = c.view(bh, N_PRE, NODES, 3).permute(0, 2, 3, 1).reshape(bh, NODES, self.coeffs)
        x = c.unsqueeze(1).repeat(1, k, 1, 1).reshape(bh * k, NODES, self.coeffs)
        graph = x.clone()
        for i, (nodes, net) in enumerate(zip(PARTS, self.nets)):
            latent = z[:, i:i + 1].repeat(1, NODES, 1)  # this part's z on every node
            out = net(torch.cat([graph, latent], dim=2))
            graph[:, nodes] = out[:, nodes, :self.coeffs]
        b = graph.shape[0]
        coeffs = graph.view(b, NODES, 3, N_PRE).permute(0, 3, 1, 2).reshape(b, N_PRE, NODES * 3)
        return torch.matmul(self.idct, coeffs).view(b, T_HIS + T_PRED, NODES, 3)


def expected_parameters():
    width = 3 * N_PRE + NZ
    head = width * HIDDEN + NODES * NODES + HIDDEN + 2 * NODES * HIDDEN
    block_layer = HIDDEN * HIDDEN + NODES * NODES + 2 * NODES * HIDDEN
    tail = HIDDEN * width + NODES * NODES + width
    return len(PARTS) * (head + 2 * BLOCKS * block_layer + tail)


def serve(name, parameters, run_ms):
    """The --serve protocol (bench/reference_process.h): "ready <parameters>", then one timed run
    per "run" line on stdin, its ms printed with 4 decimals; "quit" or EOF returns."""
    print(f"ready {parameters}", flush=True)
    while True:
        line = sys.stdin.readline()
        cmd = line.strip()
        if not line or cmd == "quit":
            return
        if cmd != "run":
            print(f"{name}: unknown command {cmd!r} (expected run or quit)", file=sys.stderr,
                  flush=True)
            sys.exit(2)
        print(f"{run_ms():.4f}", flush=True)


def main():
    p = argparse.ArgumentParser(
        description=__doc__.split("\n")[0],
        epilog="Protocol of --serve: prints 'ready <parameters>' once warmed up; then per stdin "
               "line 'run' prints one run's ms (4 decimals); 'quit' or EOF exits.")
    p.add_argument("--threads", type=int, default=1, help="torch intra-op threads (default 1)")
    p.add_argument("--rounds", type=int, default=7, help="timed runs, standalone (default 7)")
    p.add_argument("--warmup", type=int, default=3, help="untimed runs first (default 3)")
    p.add_argument("-k", type=int, default=50, help="futures per history in one run (default 50)")
    p.add_argument("--serve", action="store_true",
                   help="persistent process timing one run per 'run' line on stdin")
    a = p.parse_args()
    if a.threads < 1 or a.rounds < 1 or a.warmup < 0 or a.k < 1:
        p.error("--threads, --rounds and -k must be >= 1, --warmup >= 0")

    torch.set_num_threads(a.threads)
    torch.manual_seed(0)
    model = Generator().float().eval()
    params = sum(q.numel() for q in model.parameters())
    if params != expected_parameters():
        sys.exit(f"reference_gsps: {params} parameters, the sizes give {expected_parameters()}")
    if abs(params / 1.3e6 - 1) > 0.05:
        sys.exit(f"reference_gsps: {params} parameters, the spec says about 1.3M")
    history = torch.randn(1, T_HIS, NODES, 3)

    def run():
        t0 = time.perf_counter()
        z = torch.randn(history.shape[0] * a.k, len(PARTS), NZ)
        y = model(history, z)
        ms = 1000 * (time.perf_counter() - t0)
        return ms, y

    with torch.no_grad():
        for _ in range(a.warmup):
            _, y = run()
        if a.warmup:
            assert y.shape == (a.k, T_HIS + T_PRED, NODES, 3) and bool(torch.isfinite(y).all())
        if a.serve:
            serve("reference_gsps", params, lambda: run()[0])
            return
        print(f"reference GSPS generator, PyTorch {torch.__version__} eager, float32: {params} "
              f"parameters, {torch.get_num_threads()} thread(s)")
        times = [run()[0] for _ in range(a.rounds)]
    print(f"{a.k} futures of 1 history: {statistics.median(times):.2f} ms median of {a.rounds} "
          f"runs")
    print("runs (ms): " + " ".join(f"{t:.2f}" for t in times))


if __name__ == "__main__":
    main()
