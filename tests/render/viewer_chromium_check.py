#!/usr/bin/env python3
"""End-to-end check of `motionfork render` and its HTML viewer in headless Chromium.

    viewer_chromium_check.py MOTIONFORK_BINARY

Writes a synthetic prediction (a 17-joint walker, K futures, the legs fixed, one invalid sample),
renders it to .html and .png with the command, checks the command's errors, then loads the page
in headless Chromium with #play: the screenshot must show the figures (many colours, the left and
right limb colours) and the frame shown must have advanced (read back with --dump-dom). Standard
library only. Without Chromium it prints "SKIPPED: ..." (fails under CI=true).
"""
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

T_HIS, T_PRED, K, FPS = 10, 30, 4, 30
NAMES = ["Hips", "UpperLeg_R", "LowerLeg_R", "Foot_R", "UpperLeg_L", "LowerLeg_L", "Foot_L", "Spine",
         "Chest", "Neck", "Head", "UpperArm_L", "LowerArm_L", "Hand_L", "UpperArm_R", "LowerArm_R", "Hand_R"]
PARENTS = [-1, 0, 1, 2, 0, 4, 5, 0, 7, 8, 9, 8, 11, 12, 8, 14, 15]
# Offsets from the parent in a rest pose, metres, Y up, facing +Z.
REST = [(0, 0.95, 0), (-0.1, 0, 0), (0, -0.42, 0), (0, -0.42, 0.05), (0.1, 0, 0), (0, -0.42, 0),
        (0, -0.42, 0.05), (0, 0.2, 0), (0, 0.25, 0), (0, 0.15, 0), (0, 0.12, 0.02), (0.18, -0.05, 0),
        (0.05, -0.28, 0), (0, -0.25, 0), (-0.18, -0.05, 0), (-0.05, -0.28, 0), (0, -0.25, 0)]
FUTURE_LEFT, FUTURE_RIGHT = (0xd6, 0x27, 0x28), (0x1f, 0x77, 0xb4)  # Palette defaults


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def skip_or_fail(message):
    if os.environ.get("CI") == "true":
        fail(message + " (CI=true: the viewer test must run)")
    print("SKIPPED: " + message)
    sys.exit(0)


def pose(t, k):
    """World positions [J][3] of sample k's pose at frame t: limbs swing, samples differ."""
    out = []
    for j, (par, off) in enumerate(zip(PARENTS, REST)):
        swing = 0.25 * math.sin(2 * math.pi * t / 20 + k + (j % 3)) if j in (2, 5, 12, 15) else 0.0
        o = (off[0], off[1], off[2] + swing)
        base = out[par] if par >= 0 else (0.0, 0.0, 0.0)
        out.append(tuple(b + c for b, c in zip(base, o)))
    return out


def write_prediction(base):
    values = []
    for k in range(K):
        for t in range(T_HIS + T_PRED):
            for p in pose(t if t < T_HIS else t + 7 * k, 0 if t < T_HIS else k):
                values.extend(p)
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d, %d, 3), }" % (K, T_HIS + T_PRED, len(NAMES))
    header += " " * (63 - (10 + len(header)) % 64) + "\n"
    with open(base + ".npy", "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode())
        f.write(struct.pack("<%df" % len(values), *values))
    samples = ",".join('{"valid": %s, "violating_frames": %d, "prior_nll": null}' % (
        "false" if k == 1 else "true", 5 if k == 1 else 0) for k in range(K))
    with open(base + ".json", "w") as f:
        f.write('{"model": "synthetic", "protocol": "bandai", "history": "walk.npy", "start_frame": 0, '
                '"k": %d, "seed": 0, "fps": %d, "t_his": %d, "t_pred": %d, "skeleton": "walker", '
                '"joints": [%s], "parents": [%s], "left_right": [[4, 1], [5, 2], [6, 3], [11, 14], [12, 15], [13, 16]], '
                '"parts": [{"name": "legs", "joints": [1, 2, 3, 4, 5, 6]}, {"name": "upper", "joints": [7, 8, 9, 10, 11, 12, 13, 14, 15, 16]}], '
                '"fixed_parts": ["legs"], "array": "%s", "shape": [%d, %d, %d, 3], "samples": [%s]}\n' % (
                    K, FPS, T_HIS, T_PRED, ", ".join('"%s"' % n for n in NAMES), ", ".join(map(str, PARENTS)),
                    os.path.basename(base) + ".npy", K, T_HIS + T_PRED, len(NAMES), samples))


def read_png(path):
    """(width, height, rows of RGB tuples) of an 8-bit RGB/RGBA non-interlaced PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(path + ": not a PNG")
    at, idat = 8, b""
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    if depth != 8 or colour not in (2, 6) or interlace:
        fail("%s: expected an 8-bit RGB(A) non-interlaced PNG, got depth %d colour type %d" % (path, depth, colour))
    bpp = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    prev = bytearray(stride)
    rows = []
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if kind == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 0xff
        elif kind == 2:
            line = bytearray((a + b) & 0xff for a, b in zip(line, prev))
        elif kind == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 0xff
        elif kind == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b, c = prev[i], prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xff
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(width)])
        prev = line
    return width, height, rows


def near(c, want, tolerance=12):
    return all(abs(a - b) <= tolerance for a, b in zip(c, want))


def run(args, timeout=120):
    return subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)


def chromium(browser, profile, extra, url):
    return run([browser, "--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                "--force-color-profile=srgb", "--user-data-dir=" + profile, "--window-size=1000,700",
                "--virtual-time-budget=1000"] + extra + [url])


def frame_state(browser, profile, url):
    dom = chromium(browser, profile, ["--dump-dom"], url).stdout
    m = re.search(r'<span id="frame" data-frame="(\d+)" data-ticks="(\d+)"', dom)
    if not m:
        fail("no <span id=\"frame\" data-frame=... data-ticks=...> in the page's DOM for " + url)
    return int(m.group(1)), int(m.group(2))


def main():
    if len(sys.argv) != 2:
        fail("usage: viewer_chromium_check.py MOTIONFORK_BINARY")
    mf = sys.argv[1]
    tmp = tempfile.mkdtemp(prefix="motionfork_render_check_")
    try:
        base = os.path.join(tmp, "pred")
        write_prediction(base)
        html = os.path.join(tmp, "view.html")
        for out in (html, os.path.join(tmp, "strip.png")):
            r = run([mf, "render", base + ".json", "-o", out])
            if r.returncode != 0 or not os.path.getsize(out):
                fail("motionfork render -o %s: exit %d: %s" % (out, r.returncode, r.stderr))
        page = open(html, encoding="utf-8").read()
        if re.search(r"(src|href)\s*=\s*[\"']?\s*(https?:)?//", page):
            fail("the page loads something from the network")

        # Errors: exit status 2, a message naming what was wrong, no output file.
        bad = os.path.join(tmp, "out.jpg")
        r = run([mf, "render", base + ".json", "-o", bad])
        if r.returncode != 2 or ".png, .svg or .html" not in r.stderr or os.path.exists(bad):
            fail("-o out.jpg: expected exit 2 naming the extensions, got %d: %s" % (r.returncode, r.stderr))
        with open(os.path.join(tmp, "broken.json"), "w") as f:
            f.write('{"k": 2, "fps": ')
        r = run([mf, "render", os.path.join(tmp, "broken.json"), "-o", html])
        if r.returncode != 2 or "broken.json" not in r.stderr:
            fail("a broken prediction: expected exit 2 naming broken.json, got %d: %s" % (r.returncode, r.stderr))
        r = run([mf, "render", base + ".json", "--pick", "9", "-o", html])
        if r.returncode != 2 or "sample 9" not in r.stderr:
            fail("--pick 9 of 4 samples: expected exit 2 naming sample 9, got %d: %s" % (r.returncode, r.stderr))

        browser = shutil.which("chromium") or shutil.which("chromium-browser")
        if not browser:
            skip_or_fail("chromium is not installed (apt-get install chromium)")
        profile = os.path.join(tmp, "profile")
        url = "file://" + html
        shot = os.path.join(tmp, "shot.png")
        r = chromium(browser, profile, ["--screenshot=" + shot], url + "#play")
        if not os.path.exists(shot):
            fail("chromium wrote no screenshot: " + r.stderr[-2000:])
        width, height, rows = read_png(shot)
        pixels = [c for row in rows for c in row]
        background = sum(1 for c in pixels if c == (255, 255, 255))
        colours = len(set(pixels))
        left = sum(1 for c in pixels if near(c, FUTURE_LEFT))
        right = sum(1 for c in pixels if near(c, FUTURE_RIGHT))
        print("screenshot %dx%d: %.1f%% background, %d colours, %d left-coloured and %d right-coloured pixels" % (
            width, height, 100.0 * background / len(pixels), colours, left, right))
        if background > 0.97 * len(pixels) or colours < 50:
            fail("the screenshot is (nearly) blank")
        # The legend and a label hold ~100 such pixels; the futures' limbs several hundred more.
        if left < 300 or right < 300:
            fail("the screenshot lacks the left/right limb colours of the futures")

        frame, ticks = frame_state(browser, profile, url + "#play")
        print("#play: frame %d after %d ticks" % (frame, ticks))
        if ticks < 10 or frame == 0:
            fail("playing did not advance the frame (frame %d, %d ticks)" % (frame, ticks))
        # Without "play" it stays on the frame asked for.
        frame, ticks = frame_state(browser, profile, url + "#frame=25&sample=1")
        if frame != 25 or ticks != 0:
            fail("#frame=25: expected frame 25 and no ticks, got frame %d after %d ticks" % (frame, ticks))
        print("OK")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
