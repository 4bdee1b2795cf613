#!/usr/bin/env python3
"""From photographs to a fitted scene, end to end, as a user with JPEGs would go:

    vkrecon synth  (photographs of the bundled box: lit by a sun, exposure differing per camera)
    scripts/calibrate.sh   (Debian's COLMAP on the CPU: cameras from the photographs alone)
    vkrecon init           (the Z-up frame on the ground, a starter scene from the box template)
    vkrecon run            (the reconstruction)

and checks what each step promises against the truth the photographs were made from:
init's ground is within 1° of the true ground, the starter scene's priors hold the truth,
and the run's MAP is within 1 % of each prior's width of the truth. COLMAP's frame is the
true one up to a similarity (scale, rotation, shift), which the cameras' centres give.

The box's own textures are smooth value noise, on which SIFT finds too few features, so the
photographs here are of the same box under textures of discs of every size (what a textured
real object offers COLMAP), from a ring of 24 cameras (COLMAP needs overlapping neighbours).
`--asset house` does the same with the house and init's house template.

Exit status: 0 passed, 1 a check failed, 77 COLMAP or numpy is not installed (ctest:
skipped; scripts/test.sh installs both).
"""
import argparse
import json
import os
import shutil
import struct
import subprocess
import sys
import time
import zlib

try:
    import numpy as np
except ImportError:
    print("SKIP: numpy is not installed (scripts/bootstrap.sh python)")
    sys.exit(77)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Each asset's textures: (file, seed, discs, background, radii as shares of the side).
TEXTURES = {
    "box": [("box.png", 2, 150, (180, 90, 60), (0.04, 0.15))],
    "house": [("walls.png", 2, 150, (180, 150, 120), (0.04, 0.15)), ("roof.png", 3, 150, (120, 60, 50), (0.04, 0.15))],
}


def write_png(path, rgb):
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def discs(size, seed, count, background, radii):
    """Discs of random colour with radii log-uniform in `radii` (shares of the side): corners
    and blobs at every scale, for SIFT, and texture the likelihood's atlas can resolve."""
    rng = np.random.default_rng(seed)
    img = np.empty((size, size, 3))
    img[:] = background
    yy, xx = np.mgrid[0:size, 0:size]
    for _ in range(count):
        r = size * np.exp(rng.uniform(np.log(radii[0]), np.log(radii[1])))
        cx, cy = rng.uniform(0, size, 2)
        colour = rng.uniform(0, 255, 3)
        x0, x1 = int(max(cx - r, 0)), int(min(cx + r + 1, size))
        y0, y1 = int(max(cy - r, 0)), int(min(cy + r + 1, size))
        inside = (xx[y0:y1, x0:x1] - cx) ** 2 + (yy[y0:y1, x0:x1] - cy) ** 2 < r * r
        img[y0:y1, x0:x1][inside] = colour
    return img.astype(np.uint8)


def look_at(eye, target):
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    R = np.stack([right, np.cross(forward, right), forward])  # image y down
    return R, -R @ eye


def camera_ring(target):
    """16 cameras around at 1.8 m, 8 more above at 2.8 m between them: 640 × 480, f 560 px."""
    cameras = []
    for ring, (count, radius, height) in enumerate([(16, 3.2, 1.8), (8, 2.4, 2.8)]):
        for i in range(count):
            a = 2 * np.pi * (i + 0.5 * ring) / count
            R, t = look_at(np.array([radius * np.cos(a), radius * np.sin(a), height]), target)
            name = "cam%02d" % len(cameras)
            cameras.append({"name": name, "image": name + ".png", "width": 640, "height": 480,
                            "K": [[560, 0, 320], [0, 560, 240], [0, 0, 1]], "R": R.tolist(), "t": t.tolist()})
    return cameras


def make_true_scene(work, asset):
    """The bundled asset's scene and truth, with disc textures and the camera ring."""
    scene_dir = os.path.join(work, "truth")
    os.makedirs(os.path.join(scene_dir, "textures"))
    shutil.copy(os.path.join(ROOT, "assets", asset, "scene.json"), scene_dir)
    shutil.copy(os.path.join(ROOT, "assets", asset, "truth.json"), scene_dir)
    write_png(os.path.join(scene_dir, "textures", "ground.png"), discs(1024, 1, 1500, (120, 120, 110), (0.008, 0.05)))
    for name, seed, count, background, radii in TEXTURES[asset]:
        write_png(os.path.join(scene_dir, "textures", name), discs(1024, seed, count, background, radii))
    with open(os.path.join(scene_dir, "truth.json")) as f:
        truth = json.load(f)
    target = np.array([truth["x"], truth["y"], truth["h"] / 2])
    with open(os.path.join(scene_dir, "cameras.json"), "w") as f:
        json.dump({"cameras": camera_ring(target)}, f, indent=1)
    return scene_dir, truth


def run(step, command, log):
    start = time.time()
    with open(log, "a") as out:
        out.write("$ " + " ".join(command) + "\n")
        out.flush()
        done = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT)
    print("%-10s %6.1f s  %s" % (step, time.time() - start, " ".join(os.path.basename(c) if i == 0 else c
                                                                  for i, c in enumerate(command))), flush=True)
    if done.returncode != 0:
        with open(log) as f:
            sys.stdout.write(f.read()[-3000:])
        sys.exit("FAIL: %s exited %d (log: %s)" % (step, done.returncode, log))


def centres(cameras_json):
    with open(cameras_json) as f:
        cams = json.load(f)["cameras"]
    return {c["name"]: -np.array(c["R"]).T @ np.array(c["t"]) for c in cams}


def similarity(src, dst):
    """Umeyama: the scale c, rotation R and shift t with dst ≈ c R src + t (least squares)."""
    ms, md = src.mean(0), dst.mean(0)
    S, D = src - ms, dst - md
    U, s, Vt = np.linalg.svd(D.T @ S / len(src))
    E = np.eye(3)
    E[2, 2] = np.sign(np.linalg.det(U @ Vt))
    R = U @ E @ Vt
    c = (s * np.diag(E)).sum() / ((S ** 2).sum() / len(src))
    return c, R, md - c * R @ ms


def truth_in_scene_frame(truth, c, R, t, turn):
    """The true scene in init's frame. A box is the same box turned by 90° with w and d
    swapped (`turn` 90), a house the same turned by 180° (`turn` 180), so the yaw is brought
    into init's prior range [-45°, 45°] that way."""
    centre = c * R @ np.array([truth["x"], truth["y"], 0.0]) + t
    yaw = truth["yaw"] + np.degrees(np.arctan2(R[1, 0], R[0, 0]))
    w, d = truth["w"] * c, truth["d"] * c
    while yaw > 45:
        yaw, w, d = (yaw - 90, d, w) if turn == 90 else (yaw - 180, w, d)
    while yaw < -45:
        yaw, w, d = (yaw + 90, d, w) if turn == 90 else (yaw + 180, w, d)
    expected = {"x": centre[0], "y": centre[1], "yaw": yaw, "w": w, "d": d, "h": truth["h"] * c}
    if "rh" in truth:
        expected["rh"] = truth["rh"] * c
    return expected, centre[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--vkrecon", required=True, help="the vkrecon binary")
    parser.add_argument("--work", required=True, help="a folder for the run (emptied first)")
    parser.add_argument("--iterations", type=int, default=300, help="the run's sampler.iterations")
    parser.add_argument("--seed", type=int, default=1, help="the run's sampler.seed")
    parser.add_argument("--asset", choices=sorted(TEXTURES), default="box", help="the bundled asset, and init's template")
    args = parser.parse_args()
    if shutil.which("colmap") is None:
        print("SKIP: colmap is not installed (scripts/bootstrap.sh colmap)")
        return 77
    work = os.path.abspath(args.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    log = os.path.join(work, "log.txt")
    vkrecon = os.path.abspath(args.vkrecon)

    scene_dir, truth = make_true_scene(work, args.asset)
    synth = os.path.join(work, "synth")
    run("synth", [vkrecon, "synth", os.path.join(scene_dir, "scene.json"),
                  "--at", os.path.join(scene_dir, "truth.json"), "-o", synth, "--sun", "135", "50",
                  "--exposure", "0.1", "--supersample", "2", "-q"], log)
    photos = os.path.join(work, "photos")  # the photographs alone, as a user has them
    os.makedirs(photos)
    for name in sorted(os.listdir(synth)):
        if name.endswith(".png"):
            shutil.copy(os.path.join(synth, name), photos)
    sparse = os.path.join(work, "sparse")
    run("calibrate", [os.path.join(ROOT, "scripts", "calibrate.sh"), photos, sparse], log)
    scene2 = os.path.join(work, "scene")
    # Half size for the run (320 × 240), as a user shrinks phone photographs.
    run("init", [vkrecon, "init", os.path.join(sparse, "0"), "-o", scene2, "--images", photos,
                 "--template", args.asset, "--max-side", "320"], log)

    true_centres = centres(os.path.join(synth, "cameras.json"))
    found_centres = centres(os.path.join(scene2, "cameras.json"))
    names = sorted(true_centres)
    failures = []
    if sorted(found_centres) != names:
        failures.append("COLMAP registered %d of %d photographs" % (len(found_centres), len(names)))
        names = sorted(set(names) & set(found_centres))
    c, R, t = similarity(np.array([true_centres[n] for n in names]), np.array([found_centres[n] for n in names]))
    residual = max(np.linalg.norm(c * R @ true_centres[n] + t - found_centres[n]) for n in names) / c
    up_error = np.degrees(np.arccos(np.clip(R[2, 2], -1.0, 1.0)))
    expected, ground_z = truth_in_scene_frame(truth, c, R, t, 90 if args.asset == "box" else 180)
    print("cameras: %d, centres within %.4f m of the truth after the similarity (scale %.4f)" % (len(names), residual, c))
    print("ground: up %.3f° from the truth's, the true ground at z = %.4f (scene units)" % (up_error, ground_z))
    if up_error > 1.0:
        failures.append("init's up is %.2f° from the truth's (at most 1°)" % up_error)

    with open(os.path.join(scene2, "scene.json")) as f:
        priors = {k: v["prior"]["uniform"] for k, v in json.load(f)["parameters"].items()}
    for name, (lo, hi) in priors.items():
        if not lo <= expected[name] <= hi:
            failures.append("the starter prior of %s, [%g, %g], does not hold the truth %g" % (name, lo, hi, expected[name]))

    out = os.path.join(work, "run")
    run("run", [vkrecon, "run", os.path.join(scene2, "scene.json"), "-o", out,
                "--set", "sampler.iterations=%d" % args.iterations, "--set", "sampler.seed=%d" % args.seed], log)
    with open(os.path.join(out, "map.json")) as f:
        fitted = json.load(f)["parameters"]
    print("%-4s %10s %10s %10s %9s" % ("", "truth", "MAP", "prior", "error"))
    for name, (lo, hi) in priors.items():
        share = (fitted[name]["map"] - expected[name]) / (hi - lo)
        print("%-4s %10.4f %10.4f %10.4f %8.2f%%" % (name, expected[name], fitted[name]["map"], hi - lo, 100 * share))
        if abs(share) > 0.01:
            failures.append("%s: the MAP is %.2f %% of its prior's width from the truth (at most 1 %%)" % (name, 100 * share))
    for failure in failures:
        print("FAIL: " + failure)
    print("passed" if not failures else "%d check(s) failed; the steps' output: %s" % (len(failures), log))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
