"""The Python module `motionfork` (python/motionfork_module.cc) against the command and the files.

Run by CTest (tests/CMakeLists.txt) with the module's folder on PYTHONPATH and
MOTIONFORK_BIN (the command), MOTIONFORK_ROOT (the source tree, for models/bandai).
Fixtures are made here: a synthetic walk from `motionfork synth walk`.
"""
import errno
import json
import os
import subprocess
import threading
import time

import tarfile

import numpy as np
import pytest

import motionfork as mf

ROOT = os.environ.get("MOTIONFORK_ROOT", os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("MOTIONFORK_BIN", os.path.join(ROOT, "build", "apps", "motionfork", "motionfork"))
MODEL = os.path.join(ROOT, "models", "bandai")
SHARED = os.environ.get("MOTIONFORK_SHARED_DIR", os.path.join(ROOT, "..", "shared"))


def real_data(path):
    """path when it exists; else the test skips, or fails under CI=true (real data must run)."""
    if not os.path.exists(path):
        message = "real data: " + path + " not found"
        if os.environ.get("CI") == "true":
            pytest.fail(message + " (CI=true: real-data tests must run)")
        pytest.skip(message)
    return path


def run(*args):
    subprocess.run([BIN, "--quiet", *args], check=True, stdout=subprocess.DEVNULL)


@pytest.fixture(scope="module")
def model():
    return mf.Model.load(MODEL, threads=1)


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("walk") / "walk.bvh")
    run("synth", "walk", "--frames", "40", "-o", path)
    return path


def test_model_describes_itself(model):
    assert model.joint_names[0] == "Hips" or len(model.joint_names) == 17
    assert len(model.joint_names) == len(model.parents) == 17
    assert model.parents[0] == -1
    assert model.fps == 30
    assert model.history_frames == 15 and model.future_frames == 60
    assert "legs" in model.parts
    assert all(j in model.joint_names for joints in model.parts.values() for j in joints)
    assert model.has_prior
    assert mf.__version__.count(".") == 2


def test_predict_equals_the_command_bit_for_bit(model, walk, tmp_path):
    out = str(tmp_path / "pred")
    run("predict", walk, "--model", MODEL, "-k", "5", "--seed", "3", "--fix", "legs", "-o", out)
    expected = np.load(out + ".npy")
    got = model.predict(model.read_motion(walk), k=5, seed=3, fix=["legs"])
    assert got.dtype == np.float32
    assert got.shape == (5, 75, 17, 3) == expected.shape
    assert np.array_equal(got, expected)
    # A Motion read with its own skeleton is mapped onto the model's joints by name.
    assert np.array_equal(model.predict(mf.read_motion(walk), k=5, seed=3, fix=["legs"]), expected)
    # Same seed, same futures; another seed, others.
    assert np.array_equal(model.predict(model.read_motion(walk), k=5, seed=3, fix=["legs"]), got)
    assert not np.array_equal(model.predict(model.read_motion(walk), k=5, seed=4), got)


def test_predict_takes_float64_non_contiguous_and_batches(model, walk):
    history = model.read_motion(walk)
    single = model.predict(history, k=3, seed=1)
    assert np.array_equal(model.predict(history.astype(np.float64), k=3, seed=1), single)
    padded = np.zeros((history.shape[0], 17, 6), np.float32)
    padded[:, :, ::2] = history
    view = padded[:, :, ::2]
    assert not view.flags["C_CONTIGUOUS"]
    assert np.array_equal(model.predict(view, k=3, seed=1), single)
    other = history + np.float32(0.1)
    batch = model.predict(np.stack([history, other]), k=3, seed=1)
    assert batch.shape == (2, 3, 75, 17, 3)
    assert np.array_equal(batch[0], single)
    assert np.array_equal(batch[1], model.predict(other, k=3, seed=1))
    # The history frames of the output are the input's last ones.
    assert np.allclose(single[0, :15], history[-15:], atol=1e-6)


def test_bad_arrays_are_refused_with_clear_errors(model, walk):
    history = model.read_motion(walk)
    with pytest.raises(ValueError, match=r"J = 17, got shape \(40, 16, 3\)"):
        model.predict(history[:, :16])
    with pytest.raises(ValueError, match="float32 or float64 array, got dtype int64"):
        model.predict(np.zeros((20, 17, 3), np.int64))
    bad = history.copy()
    bad[7, 3, 1] = np.nan
    with pytest.raises(ValueError, match="frame"):
        model.predict(bad)
    with pytest.raises(ValueError, match="at least 15 frames"):
        model.predict(history[:5])
    with pytest.raises(ValueError, match="arms|legs"):  # the message lists the known parts
        model.predict(history, fix=["tail"])
    with pytest.raises(ValueError):
        model.predict(history, k=0)


def test_missing_files_raise_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError) as e:
        mf.Model.load(str(tmp_path / "nowhere"))
    assert e.value.errno == errno.ENOENT and "nowhere" in str(e.value)
    with pytest.raises(FileNotFoundError):
        mf.read_motion(str(tmp_path / "none.bvh"))
    with pytest.raises(FileNotFoundError):
        mf.Imputer.load(str(tmp_path / "none"))


def test_malformed_files_carry_the_commands_message(tmp_path):
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n")
    with pytest.raises(Exception) as e:
        mf.read_motion(str(bad))
    assert "bad.bvh" in str(e.value)
    proc = subprocess.run([BIN, "info", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert str(e.value) in proc.stderr


def test_check_reports_validity_and_prior_nll(model, walk):
    futures = model.predict(model.read_motion(walk), k=4, seed=0)
    checks = model.check(futures[:, model.history_frames:])
    assert len(checks) == 4
    for c in checks:
        assert set(c) == {"valid", "violating_frames", "undefined_frames", "violated_constraints", "nll", "failed"}
        assert isinstance(c["valid"], bool) and np.isfinite(c["nll"])
    # A pose bent past its ranges fails, naming the frames.
    broken = futures[0, model.history_frames:].copy()
    knee = model.joint_names.index("LowerLeg_L")
    broken[10:, knee] += np.array([0.0, 0.5, 0.5], np.float32)
    c = model.check(broken)[0]
    assert not c["valid"] and 10 in c["violating_frames"] and c["violated_constraints"]
    assert "angle_ranges" in c["failed"]
    # Lying on its back (Z up read as Y up): the prior's NLL is far above its bound.
    lying = futures[0].copy()[:, :, [0, 2, 1]] * np.array([1, -1, 1], np.float32)
    c = model.check(lying)[0]
    assert model.prior_bound is not None and c["nll"] > model.prior_bound
    assert "prior_nll" in c["failed"] and not c["valid"]


def test_check_history_names_what_is_off(model, walk):
    history = model.read_motion(walk)[:model.history_frames]
    fine = model.check_history(history)
    assert fine["doubts"] == [] and fine["window_score"] > fine["window_bound"]
    assert any(d.startswith("scale: ") and "millimetres" in d
               for d in model.check_history(history * 1000)["doubts"])
    lying = history[:, :, [0, 2, 1]] * np.array([1, -1, 1], np.float32)
    assert any(d.startswith("axis: ") for d in model.check_history(lying)["doubts"])


def test_prior_scores_poses_as_the_bundle_does(model, walk):
    prior = mf.Prior.load(os.path.join(MODEL, "prior"))
    poses = model.read_motion(walk)
    nll = prior.score(poses)
    assert nll.shape == (40,) and nll.dtype == np.float64
    assert np.isclose(nll.mean(), model.check(poses)[0]["nll"], rtol=1e-6)


def test_motion_files_round_trip(tmp_path, walk):
    motion = mf.read_motion(walk)
    assert len(motion) == 40 and motion.positions.shape == (40, len(motion.joint_names), 3)
    assert np.asarray(motion).shape == motion.positions.shape
    for ext in ("npy", "csv", "bvh"):
        out = str(tmp_path / ("walk." + ext))
        mf.write_motion(out, motion)
        again = mf.read_motion(out)
        assert again.fps == motion.fps
        assert np.allclose(again.positions, motion.positions, atol=1e-5), ext
        if ext != "npy":
            assert again.joint_names == motion.joint_names
    # A bare array with names and fps; NaN marks missing values in .npy.
    arr = motion.positions.copy()
    arr[3, 2, 0] = np.nan
    out = str(tmp_path / "gaps.npy")
    with pytest.raises(ValueError, match="frame 3"):
        mf.write_motion(str(tmp_path / "gaps.bvh"), arr, joint_names=motion.joint_names,
                        parents=motion.parents)
    assert not os.path.exists(tmp_path / "gaps.bvh")
    np.save(out, arr)
    read = mf.read_motion(out)
    assert np.isnan(read.positions[3, 2, 0]) and np.isnan(read.positions).sum() == 1
    with pytest.raises(ValueError, match="joint_names: expected"):
        mf.write_motion(str(tmp_path / "x.csv"), motion.positions, joint_names=["a"])


MIXAMO = {"Hips": "Hips", "Spine": "Spine1", "Chest": "Spine2", "Neck": "Neck", "Head": "Head",
          "UpperLeg_L": "LeftUpLeg", "LowerLeg_L": "LeftLeg", "Foot_L": "LeftFoot",
          "UpperLeg_R": "RightUpLeg", "LowerLeg_R": "RightLeg", "Foot_R": "RightFoot",
          "UpperArm_L": "LeftArm", "LowerArm_L": "LeftForeArm", "Hand_L": "LeftHand",
          "UpperArm_R": "RightArm", "LowerArm_R": "RightForeArm", "Hand_R": "RightHand"}


def test_another_rigs_names_map_onto_the_model(model, walk, tmp_path):
    """A Mixamo-named motion (mixamorig: prefixes, an extra finger joint) predicts as the original."""
    motion = mf.read_motion(walk)
    names = ["mixamorig:" + MIXAMO[n] for n in motion.joint_names] + ["mixamorig:LeftHandIndex1"]
    parents = list(motion.parents) + [motion.joint_names.index("Hand_L")]
    positions = np.concatenate([motion.positions, motion.positions[:, -1:] + 0.05], axis=1)
    out = str(tmp_path / "mixamo.bvh")
    mf.write_motion(out, positions, joint_names=names, parents=parents, fps=motion.fps)
    mapped = model.read_motion(out)
    assert np.allclose(mapped, model.read_motion(walk), atol=1e-5)
    # float32 products: bf16 ones (precision "auto" on a CPU with AVX512-BF16) round the network's
    # inputs, so histories 1e-6 m apart can give futures up to a millimetre apart.
    m32 = mf.Model.load(MODEL, threads=1, precision="fp32")
    a = m32.predict(mapped[:15], k=3, seed=2)
    b = m32.predict(model.read_motion(walk)[:15], k=3, seed=2)
    assert np.allclose(a, b, atol=1e-5)
    assert np.allclose(m32.predict(mf.read_motion(out), k=3, seed=2), m32.predict(mapped, k=3, seed=2),
                       atol=1e-5)
    # Upside down: turned over, with a UserWarning; forcing the up axis keeps it as it is.
    flipped = str(tmp_path / "flipped.bvh")
    mf.write_motion(flipped, motion.positions * np.array([1, -1, -1], dtype=np.float32),
                    joint_names=motion.joint_names, parents=motion.parents, fps=motion.fps)
    with pytest.warns(UserWarning, match="upside down"):
        turned = model.read_motion(flipped)
    assert np.allclose(turned, model.read_motion(walk), atol=1e-5)
    kept = mf.Model.load(MODEL, threads=1, up="y", left_right="as-labelled").read_motion(flipped)
    assert np.allclose(kept[..., 1], -model.read_motion(walk)[..., 1], atol=1e-5)
    forced = mf.Model.load(MODEL, threads=1, joint_map="smpl")
    with pytest.raises(ValueError, match="read as the smpl rig, it lacks"):
        forced.read_motion(out)


def test_impute_and_denoise_match_the_command(tmp_path, walk):
    hgvae = os.path.join(MODEL, "hgvae")
    dvae = os.path.join(MODEL, "dvae")
    imputer = mf.Imputer.load(hgvae)
    motion = mf.read_motion(walk, skeleton="bandai").positions
    assert motion.shape[1] == len(imputer.joint_names)
    mask = np.zeros(motion.shape, bool)
    mask[10:20, 5] = True
    filled = imputer.impute(motion, mask)
    assert np.array_equal(filled[~mask], motion[~mask])
    assert np.isfinite(filled).all()
    assert np.sqrt(((filled - motion)[mask] ** 2).mean()) < 0.05
    holes = motion.copy()
    holes[mask] = np.nan
    assert np.array_equal(mf.impute(hgvae, holes), filled)
    noisy = motion + np.random.default_rng(0).normal(0, 0.02, motion.shape).astype(np.float32)
    clean = mf.Denoiser.load(dvae).denoise(noisy)
    out = str(tmp_path / "noisy.npy")
    np.save(out, noisy)
    run("denoise", out, "--model", dvae, "-o", str(tmp_path / "clean.npy"), "--skeleton", "bandai")
    assert np.array_equal(clean, np.load(str(tmp_path / "clean.npy")))
    assert np.abs(clean - motion).mean() < np.abs(noisy - motion).mean()
    assert np.array_equal(mf.denoise(dvae, noisy), clean)
    with pytest.raises(ValueError, match="denoise mode"):
        mf.denoise(dvae, noisy, mode="magic")


def test_prediction_releases_the_gil(model, walk):
    history = model.read_motion(walk)
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    start = time.perf_counter()
    model.predict(np.stack([history] * 8), k=50, seed=0)
    end = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    # With the GIL held for the whole call the ticker could not run at all in between.
    assert len(during) >= max(3, int((end - start) / 0.01))


def test_real_data_a_bandai_bvh_as_the_done_when_line_reads(model, tmp_path):
    """A Bandai BVH of 22 joints, read with its own skeleton and predicted from (real data)."""
    archive = real_data(os.path.join(SHARED, "data", "bandai", "bandai-1.tar.xz"))
    with tarfile.open(archive) as tar:
        member = next(m for m in tar if m.name.endswith("_walk_elderly_001.bvh") or
                      (m.isfile() and m.name.endswith(".bvh") and "walk" in m.name))
        member.name = os.path.basename(member.name)
        tar.extract(member, tmp_path)
    path = str(tmp_path / member.name)
    motion = mf.read_motion(path)
    assert len(motion.joint_names) > 17  # the capture's own skeleton
    futures = model.predict(motion, k=50)
    assert futures.shape == (50, 75, 17, 3)
    out = str(tmp_path / "pred")
    run("predict", path, "--model", MODEL, "-k", "50", "-o", out)
    assert np.array_equal(futures, np.load(out + ".npy"))
    assert np.array_equal(model.predict(model.read_motion(path), k=50), futures)


def test_real_data_evaluate_returns_the_commands_figures(tmp_path):
    """evaluate() against `motionfork eval --json` on two synthetic walks (training clips: Bandai)."""
    data = real_data(os.path.join(SHARED, "data", "bandai"))
    clips = tmp_path / "clips"
    clips.mkdir()
    run("synth", "walk", "--frames", "120", "-o", str(clips / "walk1.bvh"))
    run("synth", "walk", "--frames", "120", "--speed", "0.8", "--heading", "40", "-o",
        str(clips / "walk2.bvh"))
    for predictor in ("zero-velocity", MODEL):
        flag = "--model" if predictor == MODEL else "--baseline"
        out = str(tmp_path / "eval.json")
        run("eval", flag, predictor, "--protocol", "bandai", "--data", data, "--clips", str(clips),
            "-k", "5", "--threads", "1", "--json", out)
        with open(out) as f:
            expected = json.load(f)
        got = mf.evaluate(predictor, "bandai", data=data, clips=str(clips), k=5, threads=1)
        for figures in (expected, got):
            del figures["seconds"]
        assert got == expected
        assert got["windows"] == 8 and got["ade"] > 0
    with pytest.raises(ValueError, match="predictor"):
        mf.evaluate("", "bandai", data=data)
