#!/usr/bin/env python3
"""Reference timing: one step of the original GSPS training in plain PyTorch eager mode (issue 30).

  taskset -c 1 /usr/bin/python3 bench/reference_gsps_training.py [--threads 1] [--steps 5]
  /usr/bin/python3 bench/reference_gsps_training.py --serve [--threads 1]

The "reference PyTorch code" our training step (bench_generator_training) is compared with: one
step of GSPS's released training loop (github.com/wei-mao-2019/gsps, train.py with
motion_pred/cfg/h36m.yml; models/LinNF.py, models/Orthogonal.py, utils/valid_angle_check.py),
rewritten here, not copied. float32, one optimiser step of the generator, on the CPU, `--threads`
intra-op threads. Needs only PyTorch (Debian: apt-get install python3-torch). Random inputs and
weights (seed 0): the time does not depend on the values.

The step, at Human3.6M's sizes (as bench_generator_training):
- 16 histories (batch_size) x 10 x 10 nested futures (nk per part, two parts), 10 pseudo
  multimodal futures each; the generator of bench/reference_gsps.py (its sizes and layout), in
  train mode (batch norm on batch statistics); latents drawn nested as train.py draws them.
- Losses as train.py's loss_function, with h36m.yml's lambdas [100, 500, 8, 25, 2, 1, 0.01, -, 100]:
  history reconstruction, limb lengths against the first frame's, diversity per part (L1 cdist,
  exp(-d / 100) within the first part's 10 futures, exp(-d / 300) within the second's), best-of-many
  against the true future, best-of-many against the pseudo futures (masked), the pose prior's
  negative log-likelihood on every third predicted frame (a third of the time each phase) and the
  angle-limit loss on every predicted pose.
- The pose prior is GSPS's LinNF(48, num_layer=3): three linear layers R = triu(R, 1) + diag(exp(
  diag R)) each followed by an orthogonal matrix applied as 48 Householder reflections in turn and a
  bias, a PReLU between them; inputs the 16 limb directions of each pose. As in train.py it is not
  optimised but its parameters keep requires_grad (backward computes their gradients too).
- The angle loss: the 16 cosines of utils/valid_angle_check.py's h36m check on every predicted
  pose, then for each angle the squared excess of the values beyond its bound(s). The released
  bounds (data/h36m_valid_angle.p) are not in the repository: BOUNDS below is one bound per angle,
  the lighter case, so the reference is not made slower than its own code would be.
- Not timed: making the batch (random here; a dataset sampler there), tensorboard logging.
- Timed: from drawing the latents to the end of Adam's step (gradient clipping at 100 included),
  per phase: generator forward, losses, backward, clip + Adam.

--serve, for A/B interleaving from C++ (bench_generator_training --reference): builds, runs two
warm-up steps, prints "ready <parameters>", then reads stdin line by line: "run" -> one step,
prints its ms with 4 decimals; "quit" or EOF -> exits (anything else: a message on stderr, exit
status 2). Every reply is flushed.
"""
import argparse
import math
import os
import statistics
import sys
import time

import torch
from torch import nn
from torch.nn import functional as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from reference_gsps import NODES, NZ, PARTS, T_HIS, T_PRED, Generator, serve  # noqa: E402

BATCH, NK, MODALITY = 16, 10, 10
LAMBDAS = [100.0, 500.0, 8.0, 25.0, 2.0, 1.0, 0.01, 0.01, 100.0]  # h36m.yml nf_specs.lambdas
ALPHA, BETA = 100.0, 300.0  # the diversity scales of the two parts (train.py's defaults)
# Human3.6M's 17-joint parents (the root is joint 0; the generator's 16 nodes are joints 1..16).
PARENTS = [-1, 0, 1, 2, 0, 4, 5, 0, 7, 8, 9, 8, 11, 12, 8, 14, 15]
# One bound per angle (cosines): ("lower", v) penalises cos < v, ("upper", v) cos > v.
BOUNDS = {
    "Spine2Hip": ("lower", -0.5), "Leg2HipPlane": ("lower", -0.9),
    "Shoulder2Hip": ("upper", 0.9), "Leg2ShoulderPlane": ("lower", -0.9),
    "Shoulder2Shoulder": ("upper", 0.5), "Neck2Spine": ("lower", -0.5),
    "Spine2HipPlane1": ("lower", -0.6), "Spine2HipPlane2": ("upper", 0.6),
    "ShoulderPlane2HipPlane": ("lower", -0.3), "Head2Neck": ("lower", -0.3),
    "Head2HeadTop": ("lower", -0.5), "HeadVerticalPlane2HipPlane": ("lower", -0.9),
    "Shoulder2Neck": ("upper", 0.3),
}


class Householder(nn.Module):
    """An orthogonal d x d map as d reflections (I - 2 v v^T / v^T v), the last row's first."""

    def __init__(self, d):
        super().__init__()
        u = torch.empty(d, d).normal_(0, 0.5)
        self.u = nn.Parameter(u / u.norm(dim=1, keepdim=True))

    def forward(self, x):
        for r in range(self.u.shape[0] - 1, -1, -1):
            v = self.u[r:r + 1]
            x = x - 2 * (x @ v.t() @ v) / (v @ v.t())[0, 0]
        return x


class LinearQR(nn.Module):
    """x -> Q (R x) + b with R upper triangular (exp on its diagonal): its log-determinant is
    the sum of R's raw diagonal."""

    def __init__(self, d):
        super().__init__()
        self.q = Householder(d)
        self.r = nn.Parameter(torch.empty(d, d))
        self.bias = nn.Parameter(torch.empty(d))
        nn.init.kaiming_uniform_(self.r, a=math.sqrt(5))
        nn.init.uniform_(self.bias, -d ** -0.5, d ** -0.5)

    def forward(self, x, logdet):
        diag = torch.diag(self.r)
        r = torch.triu(self.r, diagonal=1) + torch.diag(torch.exp(diag))
        x = self.q(x.matmul(r.t())) + self.bias
        return x, logdet + diag[None, :].repeat([x.shape[0], 1]).sum(dim=1)


class FlowPReLU(nn.Module):
    def __init__(self):
        super().__init__()
        self.weight = nn.Parameter(torch.tensor([0.25]))

    def forward(self, x, logdet):
        s = torch.zeros_like(x)
        s[x < 0] = torch.log(self.weight)
        return F.prelu(x, self.weight), logdet + s.sum(dim=1)


class PosePrior(nn.Module):
    """GSPS's LinNF with num_layer linear layers and a PReLU between each two."""

    def __init__(self, d, num_layer=3):
        super().__init__()
        layers = []
        for _ in range(num_layer - 1):
            layers += [LinearQR(d), FlowPReLU()]
        self.layers = nn.ModuleList(layers + [LinearQR(d)])

    def forward(self, x):
        logdet = 0
        for layer in self.layers:
            x, logdet = layer(x, logdet)
        return x, logdet


def cos(a, b):
    return (a * b).sum(dim=1) / a.norm(dim=1) / b.norm(dim=1)


def h36m_angle_cosines(p):
    """p [n, 16, 3] root-relative joints 1..16 -> {angle: cosines}, valid_angle_check's h36m set."""
    j = [p[:, i] for i in range(NODES)]
    out = {}
    out["Spine2Hip"] = torch.vstack((cos(j[3], j[6]), cos(j[0], j[6])))
    nl = torch.cross(j[3], j[4] - j[3], dim=1)
    nr = torch.cross(j[1] - j[0], j[0], dim=1)
    out["Leg2HipPlane"] = torch.vstack((cos(nl, j[5] - j[4]), cos(nr, j[2] - j[1])))
    out["Shoulder2Hip"] = torch.vstack((cos(j[10] - j[7], j[3]), cos(j[13] - j[7], j[0])))
    n = torch.cross(j[13], j[10], dim=1)
    out["Leg2ShoulderPlane"] = torch.vstack((cos(n, j[4]), cos(n, j[1])))
    out["Shoulder2Shoulder"] = cos(j[13] - j[7], j[10] - j[7])
    out["Neck2Spine"] = cos(j[7] - j[6], j[6])
    nl = torch.cross(j[4] - j[3], j[3], dim=1)
    dir_l = cos(j[3], torch.cross(j[6], nl, dim=1))
    gt_l = cos(nl, j[6])
    nr = torch.cross(j[0], j[1] - j[0], dim=1)
    dir_r = cos(j[0], torch.cross(nr, j[6], dim=1))
    gt_r = cos(nr, j[6])
    out["Spine2HipPlane1"] = torch.hstack((gt_l[dir_l < 0], gt_r[dir_r < 0]))
    out["Spine2HipPlane2"] = torch.hstack((gt_l[dir_l >= 0], gt_r[dir_r >= 0]))
    out["ShoulderPlane2HipPlane"] = cos(torch.cross(j[7] - j[0], j[7] - j[3], dim=1),
                                        torch.cross(j[10], j[13], dim=1))
    out["Head2Neck"] = cos(j[7] - j[6], j[8] - j[7])
    out["Head2HeadTop"] = cos(j[9] - j[8], j[8] - j[7])
    n0 = torch.cross(j[9] - j[8], j[8] - j[7], dim=1)
    out["HeadVerticalPlane2HipPlane"] = cos(torch.cross(n0, j[9] - j[7], dim=1),
                                            torch.cross(j[7] - j[0], j[7] - j[3], dim=1))
    out["Shoulder2Neck"] = torch.vstack((cos(j[10] - j[7], j[6] - j[7]),
                                         cos(j[13] - j[7], j[6] - j[7])))
    return out


def angle_loss(y):
    loss = torch.tensor(0.0)
    for name, c in h36m_angle_cosines(y.reshape(-1, NODES, 3)).items():
        side, bound = BOUNDS[name]
        beyond = c < bound if side == "lower" else c > bound
        if torch.any(beyond):
            loss = loss + (c[beyond] - bound).pow(2).mean()
    return loss


def part_columns(nodes):
    return [3 * n for n in nodes] + [3 * n + 1 for n in nodes] + [3 * n + 2 for n in nodes]


def diversity_losses(y_g):
    """y_g [t_pred, B * NK * NK, 48] -> the two parts' exp(-L1 distance / scale) means."""
    y = y_g.permute(1, 0, 2).contiguous().view(BATCH, NK, NK, T_PRED, -1)
    upper = torch.tril(torch.ones(NK, NK)) == 0
    first = y[:, :, 0][..., part_columns(PARTS[0])].reshape(BATCH, NK, -1)
    second = y[..., part_columns(PARTS[1])].reshape(BATCH * NK, NK, -1)
    losses = [(-torch.cdist(first, first, p=1)[:, upper] / ALPHA).exp().mean(),
              (-torch.cdist(second, second, p=1)[:, upper] / BETA).exp().mean()]
    with torch.no_grad():  # logged by train.py: the mean distance of all 100 futures
        flat = y.reshape(BATCH, NK * NK, -1)
        pairs = torch.tril(torch.ones(NK * NK, NK * NK)) == 0
        spread = torch.cdist(flat, flat, p=2)[:, pairs].mean()
    return losses, spread


def recon_losses(y_g, y, y_mm):
    y_g = y_g.view(y_g.shape[0], BATCH, NK * NK, y_g.shape[2])
    diff = y_g - y.unsqueeze(2)
    recon = diff.pow(2).sum(dim=-1).sum(dim=0).min(dim=1)[0].mean()
    with torch.no_grad():
        ade = torch.norm(diff, dim=-1).mean(dim=0).min(dim=1)[0].mean()
    diff = y_g[:, :, :, None, :] - y_mm[:, :, None, :, :]
    mask = y_mm.abs().sum(-1).sum(0) > 1e-6
    recon_mm = diff.pow(2).sum(dim=-1).sum(dim=0).min(dim=1)[0][mask].mean()
    if torch.isnan(recon_mm):
        recon_mm = torch.zeros_like(recon)
    return recon, recon_mm, ade


def limb_directions(frames):
    """[n, 16, 3] root-relative joints -> [n, 48] unit vectors parent -> child (the root at 0)."""
    p = torch.cat([torch.zeros_like(frames[:, :1]), frames], dim=1)
    d = p[:, 1:] - p[:, PARENTS[1:]]
    return (d / torch.norm(d, dim=-1, keepdim=True)).reshape(frames.shape[0], -1)


class Step:
    """Everything one training step needs, built once; __call__ runs and times one step."""

    def __init__(self):
        self.model = Generator().float().train()
        self.prior = PosePrior(3 * NODES).float()
        self.optimizer = torch.optim.Adam(self.model.parameters(), lr=1e-3)
        self.normal = torch.distributions.Normal(torch.tensor(0.0), torch.tensor(1.0))
        self.parameters = sum(q.numel() for q in self.model.parameters())

    def nested_latents(self):
        z = None
        for _ in PARTS:
            if z is None:
                z = torch.randn(BATCH, NK, 1, NZ)
            else:
                z = z.repeat_interleave(NK, dim=1)
                z = torch.cat([z, torch.randn(BATCH, z.shape[1], 1, NZ)], dim=2)
        return z.reshape(-1, len(PARTS), NZ)

    def __call__(self):
        """One step on fresh random data -> (total ms, {phase: ms}, loss)."""
        frames = T_HIS + T_PRED
        traj = torch.randn(frames, BATCH, 3 * NODES) * 0.2  # [T, B, 48] as train.py's traj
        traj_mm = torch.randn(frames, BATCH, MODALITY, 3 * NODES) * 0.2
        history = traj[:T_HIS].permute(1, 0, 2).reshape(BATCH, T_HIS, NODES, 3).contiguous()
        t0 = time.perf_counter()
        with torch.no_grad():
            z = self.nested_latents()
        out = self.model(history, z)  # [B * 100, T, 16, 3]
        est = out.reshape(out.shape[0], frames, -1).transpose(0, 1)  # [T, B * 100, 48]
        t1 = time.perf_counter()
        y_g = est[T_HIS:]
        div, spread = diversity_losses(y_g)
        recon, recon_mm, ade = recon_losses(y_g, traj[T_HIS:], traj_mm[T_HIS:])
        xest = est[:T_HIS].reshape(T_HIS, BATCH, NK * NK, -1)
        loss_x = torch.mean((xest - traj[:T_HIS].unsqueeze(2)).pow(2).sum(dim=-1))
        first = torch.cat([torch.zeros(BATCH, 1, 3), traj[0].reshape(BATCH, NODES, 3)], dim=1)
        limb_gt = torch.norm(first[:, 1:] - first[:, PARENTS[1:]], dim=2)[None, :, None, :]
        joints = est.reshape(frames, BATCH, NK * NK, NODES, 3)
        pest = torch.zeros(frames, BATCH, NK * NK, NODES + 1, 3)
        pest[:, :, :, 1:] = joints
        limb = torch.norm(pest[:, :, :, 1:] - pest[:, :, :, PARENTS[1:]], dim=4)
        loss_limb = torch.mean((limb_gt - limb).pow(2).sum(dim=3))
        loss_ang = angle_loss(y_g)
        phase = int(torch.randint(3, ()).item())
        z_prior, logdet = self.prior(limb_directions(est[T_HIS + phase::3].reshape(-1, NODES, 3)))
        prior_lkh = self.normal.log_prob(z_prior).sum(dim=-1)
        loss = (loss_x * LAMBDAS[0] + loss_limb * LAMBDAS[1] + div[0] * LAMBDAS[2] +
                div[1] * LAMBDAS[3] + recon * LAMBDAS[4] + recon_mm * LAMBDAS[5] -
                prior_lkh.mean() * LAMBDAS[6])
        if loss_ang > 0:
            loss = loss + loss_ang * LAMBDAS[8]
        logged = [t.item() for t in (loss, loss_x, loss_limb, loss_ang, div[0], div[1], spread,
                                     recon, recon_mm, ade, prior_lkh.mean(), logdet.mean())]
        t2 = time.perf_counter()
        self.optimizer.zero_grad()
        loss.backward()
        t3 = time.perf_counter()
        torch.nn.utils.clip_grad_norm_(list(self.model.parameters()), max_norm=100)
        self.optimizer.step()
        t4 = time.perf_counter()
        ms = lambda a, b: 1000 * (b - a)  # noqa: E731
        phases = {"forward": ms(t0, t1), "losses": ms(t1, t2), "backward": ms(t2, t3),
                  "clip + Adam": ms(t3, t4)}
        return ms(t0, t4), phases, logged[0]


def main():
    p = argparse.ArgumentParser(
        description=__doc__.split("\n")[0],
        epilog="Protocol of --serve: prints 'ready <parameters>' after two warm-up steps; then "
               "per stdin line 'run' prints one step's ms (4 decimals); 'quit' or EOF exits.")
    p.add_argument("--threads", type=int, default=1, help="torch intra-op threads (default 1)")
    p.add_argument("--steps", type=int, default=5, help="timed steps, standalone (default 5)")
    p.add_argument("--warmup", type=int, default=2, help="untimed steps first (default 2)")
    p.add_argument("--serve", action="store_true",
                   help="persistent process timing one step per 'run' line on stdin")
    a = p.parse_args()
    if a.threads < 1 or a.steps < 1 or a.warmup < 0:
        p.error("--threads and --steps must be >= 1, --warmup >= 0")

    torch.set_num_threads(a.threads)
    torch.manual_seed(0)
    step = Step()
    for _ in range(a.warmup):
        _, _, loss = step()
        if not math.isfinite(loss):
            sys.exit(f"reference_gsps_training: the warm-up step's loss is {loss}")
    if a.serve:
        serve("reference_gsps_training", step.parameters, lambda: step()[0])
        return
    print(f"reference GSPS training step, PyTorch {torch.__version__} eager, float32: "
          f"{step.parameters} generator parameters, {torch.get_num_threads()} thread(s), "
          f"{BATCH} histories x {NK * NK} futures")
    runs = [step() for _ in range(a.steps)]
    for name in runs[0][1]:
        print(f"  {name}: {statistics.median(r[1][name] for r in runs):.1f} ms median")
    print(f"training step: {statistics.median(r[0] for r in runs):.1f} ms median of {a.steps}")
    print("steps (ms): " + " ".join(f"{r[0]:.1f}" for r in runs))


if __name__ == "__main__":
    main()
