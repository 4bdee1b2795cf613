#!/usr/bin/env python3
"""Writes the bundled example scenes: scene.json, truth.json, cameras.json and albedo
textures for `box`, `house`, `stairs` and `poster` (after the thesis's experiments), and
`focal`, the box with camera parameters estimated too (§4.5.3). The clutter assets,
`house_annex`, `crate_clutter` and `house_cloth`, also get synth.json: the *true* scene `vkrecon synth`
photographs (lit by a sun, exposure differing between cameras, with structure that
scene.json, the model reconstructed with, leaves out).

Reference images are NOT written here: `vkrecon synth` makes them from truth.json, so they
never drift from the renderer. Only the Python standard library is used; the output is
deterministic, so re-running it changes nothing unless this script changed.

    python3 assets/make_assets.py          # rewrites assets/*/
"""
import json
import math
import os
import random
import re
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# Every asset's settings. σ is estimated at the mode ("auto"): a given σ that does not match
# the images unbalances the χ² correction (docs/internals/LIKELIHOOD.md). 600 iterations keep the
# default run of every asset within 5 minutes on a 2-core machine without a GPU.
LIKELIHOOD = {"kind": "surface", "sigma": "auto", "weights": "angle", "atlas": 256, "levels": 3}
SAMPLER = {"iterations": 600, "chains": 4, "batch": 16, "seed": 1}


# ---------------------------------------------------------------- textures (PNG, RGB 8-bit)
def write_png(path, width, height, pixels):
    """pixels: list of rows, each a list of (r, g, b) in 0..255."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in pixels)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def value_noise(size, seed, octaves=5):
    """Tileable multi-octave value noise in [0,1]: texture at every scale, so the
    photo-consistency likelihood has something to lock onto at every pyramid level."""
    rng = random.Random(seed)
    out = [[0.0] * size for _ in range(size)]
    total = 0.0
    for o in range(octaves):
        cells = 4 << o
        grid = [[rng.random() for _ in range(cells)] for _ in range(cells)]
        amp = 0.6 ** o
        total += amp
        for y in range(size):
            fy = y * cells / size
            y0 = int(fy)
            ty = fy - y0
            ty = ty * ty * (3 - 2 * ty)
            for x in range(size):
                fx = x * cells / size
                x0 = int(fx)
                tx = fx - x0
                tx = tx * tx * (3 - 2 * tx)
                a = grid[y0 % cells][x0 % cells]
                b = grid[y0 % cells][(x0 + 1) % cells]
                c = grid[(y0 + 1) % cells][x0 % cells]
                d = grid[(y0 + 1) % cells][(x0 + 1) % cells]
                out[y][x] += amp * ((a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty)
    return [[v / total for v in row] for row in out]


def texture(path, seed, base, contrast=0.9, size=128):
    """A noise texture tinted around colour `base` (0..1 RGB)."""
    n = value_noise(size, seed)
    m = value_noise(size, seed + 1000, octaves=3)
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            v = (n[y][x] - 0.5) * 2.0 * contrast
            w = (m[y][x] - 0.5) * 0.5
            r = base[0] * (1 + v) + w * 0.3
            g = base[1] * (1 + v) - w * 0.2
            b = base[2] * (1 + v * 0.8) + w * 0.1
            row.append(tuple(max(0, min(255, int(round(255 * c)))) for c in (r, g, b)))
        rows.append(row)
    write_png(path, size, size, rows)


def poster_texture(path, size=128):
    """Bold stripes and blocks, like printed graphics, on top of fine noise."""
    n = value_noise(size, 77)
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            band = (x // 16 + y // 24) % 3
            base = [(0.85, 0.2, 0.15), (0.95, 0.85, 0.3), (0.15, 0.3, 0.7)][band]
            v = 0.7 + 0.6 * (n[y][x] - 0.5)
            row.append(tuple(max(0, min(255, int(round(255 * c * v)))) for c in base))
        rows.append(row)
    write_png(path, size, size, rows)


# ---------------------------------------------------------------- meshes (glTF binary)
def write_sphere_glb(path, rings=16, segments=32):
    """A UV sphere of diameter 1 centred at the origin, with normals and TEXCOORD_0 (u around,
    v from the top): one face of the atlas, painted once by the node's albedo."""
    positions, normals, uvs, indices = [], [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings          # from the +Y pole (glTF is Y-up)
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            normals.append(n)
            positions.append(tuple(0.5 * c for c in n))
            uvs.append((j / segments, i / rings))
    for i in range(rings):
        for j in range(segments):
            a = i * (segments + 1) + j
            b = a + segments + 1
            if i > 0:
                indices += [a, b, a + 1]
            if i < rings - 1:
                indices += [a + 1, b, b + 1]
    blob = b"".join(struct.pack("<3f", *p) for p in positions)
    blob += b"".join(struct.pack("<3f", *n) for n in normals)
    blob += b"".join(struct.pack("<2f", *t) for t in uvs)
    blob += b"".join(struct.pack("<I", k) for k in indices)
    nv = len(positions)
    views = [(0, 12 * nv), (12 * nv, 12 * nv), (24 * nv, 8 * nv), (32 * nv, 4 * len(indices))]
    gltf = {
        "asset": {"version": "2.0", "generator": "vkrecon assets/make_assets.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "mode": 4}]}],
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
             "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]},
            {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": nv, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5125, "count": len(indices), "type": "SCALAR"}],
    }
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


# ---------------------------------------------------------------- cameras
def look_at(eye, target, name, image, width=640, height=480, f=560.0):
    """An OpenCV camera (x right, y down, z forward) at `eye` looking at `target`."""
    z = [t - e for t, e in zip(target, eye)]
    zn = math.sqrt(sum(c * c for c in z))
    z = [c / zn for c in z]
    x = [z[1] * 1 - z[2] * 0, z[2] * 0 - z[0] * 1, 0.0]  # z × up(0,0,1)
    xn = math.sqrt(sum(c * c for c in x))
    x = [c / xn for c in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    R = [x, y, z]
    t = [-sum(R[r][c] * eye[c] for c in range(3)) for r in range(3)]
    K = [[f, 0.0, width / 2], [0.0, f, height / 2], [0.0, 0.0, 1.0]]
    rnd = lambda v: round(v, 12)
    return {"name": name, "image": image, "width": width, "height": height,
            "K": [[rnd(v) for v in row] for row in K],
            "R": [[rnd(v) for v in row] for row in R], "t": [rnd(v) for v in t]}


def ring(n, radius, height, target, start_deg=0.0, span_deg=360.0, jitter=0.0, seed=0):
    rng = random.Random(seed)
    cams = []
    for i in range(n):
        a = math.radians(start_deg + span_deg * (i + 0.5) / n) if span_deg < 360 else math.radians(start_deg + 360.0 * i / n)
        r = radius * (1 + jitter * (rng.random() - 0.5))
        h = height * (1 + jitter * (rng.random() - 0.5))
        eye = [target[0] + r * math.cos(a), target[1] + r * math.sin(a), h]
        cams.append(look_at(eye, target, "cam%d" % i, "cam%d.png" % i))
    return cams


# ---------------------------------------------------------------- scenes
def uniform(lo, hi):
    return {"prior": {"uniform": [lo, hi]}}


GROUND = {"name": "ground", "primitive": "plane", "transforms": [{"scale": [5, 5, 1]}],
          "albedo": "textures/ground.png"}


# The box asset's box, also the focal asset's.
BOX_NODE = {"name": "box", "primitive": "box", "albedo": "textures/box.png",
            "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]},
                           {"scale": ["w", "d", "h"]}]}


def box_parameters():
    return {"x": uniform(-0.5, 0.5), "y": uniform(-0.5, 0.5), "yaw": uniform(-45, 45),
            "w": uniform(0.3, 1.5), "d": uniform(0.3, 1.5), "h": uniform(0.2, 1.0)}


# How synth photographs the clutter assets (a `synth` block): a sun 40° high with cast
# shadows, exposures that differ by up to ±30 % between cameras, 3×3 samples per pixel.
PHOTO = {"sun": [135, 40], "ambient": 0.3, "exposure": 0.3, "supersample": 3}


def write_asset(name, scene, truth, cameras, textures, synth_scene=None, meshes=None, variants=None):
    folder = os.path.join(HERE, name)
    os.makedirs(os.path.join(folder, "textures"), exist_ok=True)
    for file, make in textures.items():
        make(os.path.join(folder, "textures", file))
    for file, make in (meshes or {}).items():
        os.makedirs(os.path.join(folder, "meshes"), exist_ok=True)
        make(os.path.join(folder, "meshes", file))
    scenes = {"scene.json": scene}
    if synth_scene:
        scenes["synth.json"] = synth_scene
    scenes.update(variants or {})
    for file, body in scenes.items():
        full = {"version": 1, "images": "images/", "cameras": "cameras.json"}
        full.update(body)
        with open(os.path.join(folder, file), "w") as f:
            json.dump(full, f, indent=2)
            f.write("\n")
    with open(os.path.join(folder, "truth.json"), "w") as f:
        json.dump(truth, f, indent=2)
        f.write("\n")
    with open(os.path.join(folder, "cameras.json"), "w") as f:
        json.dump({"cameras": cameras}, f, indent=2)
        f.write("\n")


def main():
    ground_tex = {"ground.png": lambda p: texture(p, 1, (0.45, 0.42, 0.35))}

    # box: a box on a ground plane, 9 cameras (thesis §7, Figs 7.12–7.14).
    write_asset("box", {
        "parameters": box_parameters(),
        "nodes": [GROUND, BOX_NODE],
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }, {"x": 0.12, "y": -0.08, "yaw": 17.0, "w": 0.8, "d": 0.6, "h": 0.5},
        ring(9, 3.0, 1.8, [0.0, 0.0, 0.3], jitter=0.15, seed=2),
        dict(ground_tex, **{"box.png": lambda p: texture(p, 2, (0.7, 0.35, 0.25))}))

    # house: box walls + prism roof, 7 cameras (the example scene of docs/guide/SCENE_FORMAT.md,
    # "Worked example: the house").
    write_asset("house", {
        "parameters": {"x": uniform(-0.5, 0.5), "y": uniform(-0.5, 0.5), "yaw": uniform(-45, 45),
                       "w": uniform(0.3, 1.5), "d": uniform(0.3, 1.5), "h": uniform(0.2, 1.0),
                       "rh": uniform(0.05, 0.6)},
        "nodes": [GROUND,
                  {"name": "walls", "primitive": "box", "albedo": "textures/walls.png",
                   "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]},
                                  {"scale": ["w", "d", "h"]}]},
                  {"name": "roof", "parent": "walls", "primitive": "prism", "albedo": "textures/roof.png",
                   "transforms": [{"translate": [0, 0, 1]}, {"scale": [1, 1, "rh/h"]}]}],
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }, {"x": 0.1, "y": 0.05, "yaw": -12.0, "w": 1.1, "d": 0.8, "h": 0.6, "rh": 0.35},
        ring(7, 3.5, 2.2, [0.0, 0.0, 0.4], jitter=0.15, seed=3),
        dict(ground_tex, **{"walls.png": lambda p: texture(p, 3, (0.8, 0.75, 0.6)),
                            "roof.png": lambda p: texture(p, 4, (0.55, 0.2, 0.15))}))

    # stairs: 4 steps sharing rise, run and width; 6 cameras in front of the risers.
    steps = [{"name": "step%d" % k, "parent": "stairs", "primitive": "box",
              "albedo": "textures/steps.png",
              "transforms": [{"translate": [0, "%g*run" % (k + 0.5), 0]},
                             {"scale": ["width", "run", "rise" if k == 0 else "%d*rise" % (k + 1)]}]}
             for k in range(4)]
    write_asset("stairs", {
        "parameters": {"x": uniform(-0.4, 0.4), "y": uniform(-0.4, 0.4), "yaw": uniform(-30, 30),
                       "width": uniform(0.5, 1.5), "run": uniform(0.15, 0.45), "rise": uniform(0.1, 0.3)},
        "nodes": [GROUND,
                  {"name": "stairs", "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]}]}]
                 + steps,
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }, {"x": 0.05, "y": -0.1, "yaw": 8.0, "width": 1.0, "run": 0.28, "rise": 0.18},
        ring(6, 3.0, 1.9, [0.0, 0.4, 0.3], start_deg=200, span_deg=140, jitter=0.1, seed=4),
        dict(ground_tex, **{"steps.png": lambda p: texture(p, 5, (0.6, 0.6, 0.62))}))

    # poster: a cylinder carrying a poster, 6 cameras.
    write_asset("poster", {
        "parameters": {"x": uniform(-0.4, 0.4), "y": uniform(-0.4, 0.4),
                       "diameter": uniform(0.2, 0.9), "height": uniform(0.6, 2.0)},
        "nodes": [GROUND,
                  {"name": "column", "primitive": "cylinder", "albedo": "textures/poster.png",
                   "transforms": [{"translate": ["x", "y", 0]}, {"scale": ["diameter", "diameter", "height"]}]}],
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }, {"x": -0.05, "y": 0.1, "diameter": 0.5, "height": 1.2},
        ring(6, 3.0, 1.7, [0.0, 0.0, 0.6], jitter=0.15, seed=5),
        dict(ground_tex, **{"poster.png": poster_texture}))

    # focal: the box scene and cameras, but the photographs were taken with a focal length
    # 4 % longer than the calibration says and with the principal point 6 px right of it,
    # and cam4 stood 8 cm higher than its recorded pose (thesis §4.5.3). The camera file
    # keeps the nominal calibration, with f (a factor on fx and fy), px (pixels added to cx)
    # and dz (metres added to cam4's height) written into it as expressions.
    cameras = ring(9, 3.0, 1.8, [0.0, 0.0, 0.3], jitter=0.15, seed=2)
    for cam in cameras:
        (fx, _, cx), (_, fy, cy), _ = cam["K"]
        cam["K"] = [["%g*f" % fx, 0.0, "%g + px" % cx], [0.0, "%g*f" % fy, cy], [0.0, 0.0, 1.0]]
    cameras[4]["pose"] = [{"translate": [0, 0, "dz"]}]
    write_asset("focal", {
        "parameters": dict(box_parameters(), f=uniform(0.9, 1.1), px=uniform(-20, 20),
                           dz=uniform(-0.2, 0.2)),
        "nodes": [GROUND, BOX_NODE],
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }, {"x": 0.12, "y": -0.08, "yaw": 17.0, "w": 0.8, "d": 0.6, "h": 0.5, "f": 1.04, "px": 6.0, "dz": 0.08},
        cameras,
        dict(ground_tex, **{"box.png": lambda p: texture(p, 2, (0.7, 0.35, 0.25))}))

    clutter_assets(ground_tex)
    edge_assets()


def clutter_assets(ground_tex):
    """Scenes whose photographs hold more than the model: what every real photo set does."""
    # house_annex: the house's walls and roof (the model: the `house` asset's scene), photographed
    # with a lower annex against its +x end, a chimney, window frames standing 2 cm proud of the
    # long walls, a door on the -x gable, and eaves overhanging the walls by 3 cm (a 30 cm
    # overhang on a house ten times this size). The overhang is model error that moves the
    # truth itself: the walls say w, the roof w + 6 cm (docs/guide/REAL_PHOTOS.md measures how
    # much).
    house_params = {"x": uniform(-0.5, 0.5), "y": uniform(-0.5, 0.5), "yaw": uniform(-45, 45),
                    "w": uniform(0.3, 1.5), "d": uniform(0.3, 1.5), "h": uniform(0.2, 1.0),
                    "rh": uniform(0.05, 0.6)}
    house_truth = {"x": 0.1, "y": 0.05, "yaw": -12.0, "w": 1.1, "d": 0.8, "h": 0.6, "rh": 0.35}
    walls = {"name": "walls", "primitive": "box", "albedo": "textures/walls.png",
             "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]},
                            {"scale": ["w", "d", "h"]}]}
    roof = {"name": "roof", "parent": "walls", "primitive": "prism", "albedo": "textures/roof.png",
            "transforms": [{"translate": [0, 0, 1]}, {"scale": [1, 1, "rh/h"]}]}
    # The true scene hangs everything from an unscaled frame at the house's position, so the
    # extra structure keeps its own size; at the truth it reproduces walls and roof exactly.
    frame = {"name": "frame", "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]}]}
    true_walls = {"name": "walls", "parent": "frame", "primitive": "box", "albedo": "textures/walls.png",
                  "transforms": [{"scale": ["w", "d", "h"]}]}
    true_roof = {"name": "roof", "parent": "frame", "primitive": "prism", "albedo": "textures/roof.png",
                 "transforms": [{"translate": [0, 0, "h"]}, {"scale": ["w + 0.06", "d + 0.06", "rh"]}]}
    extras = [
        {"name": "annex", "parent": "frame", "primitive": "box", "albedo": "textures/annex.png",
         "transforms": [{"translate": ["w/2 + 0.21", 0, 0]}, {"scale": [0.42, 0.56, 0.34]}]},
        {"name": "annex_roof", "parent": "frame", "primitive": "prism", "albedo": "textures/roof.png",
         "transforms": [{"translate": ["w/2 + 0.23", 0, 0.34]}, {"scale": [0.46, 0.62, 0.12]}]},
        {"name": "chimney", "parent": "frame", "primitive": "box", "albedo": "textures/chimney.png",
         "transforms": [{"translate": [-0.28, 0.16, "h"]}, {"scale": [0.12, 0.12, "rh + 0.12"]}]},
        {"name": "door", "parent": "frame", "primitive": "box", "albedo": "textures/window.png",
         "transforms": [{"translate": ["-w/2 - 0.01", 0.05, 0]}, {"scale": [0.02, 0.2, 0.36]}]},
    ]
    for side, sign in (("front", -1), ("back", 1)):
        for k, along in enumerate((-0.32, 0.0, 0.32)):
            extras.append({"name": "window_%s%d" % (side, k), "parent": "frame", "primitive": "box",
                           "albedo": "textures/window.png",
                           "transforms": [{"translate": [along, "%g*(d/2 + 0.01)" % sign, 0.24]},
                                          {"scale": [0.17, 0.02, 0.2]}]})
    # What a user does who sees the roof overhang the walls: one more parameter, the overhang e,
    # with the roof scaled to (w + 2e) × (d + 2e) (docs/guide/REAL_PHOTOS.md, "The synthetic clutter
    # assets": without it the MAP follows the roof's planes, not the walls).
    eaves_roof = dict(roof, transforms=[{"translate": [0, 0, 1]},
                                        {"scale": ["1 + 2*e/w", "1 + 2*e/d", "rh/h"]}])
    house_annex_scene = {
        "parameters": house_params,
        "nodes": [GROUND, walls, roof],
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }
    eaves_scene = dict(house_annex_scene, parameters=dict(house_params, e=uniform(0.0, 0.1)),
                       nodes=[GROUND, walls, eaves_roof])
    write_asset("house_annex", house_annex_scene, house_truth, ring(7, 3.5, 2.2, [0.0, 0.0, 0.4], jitter=0.15, seed=3),
        dict(ground_tex, **{"walls.png": lambda p: texture(p, 3, (0.8, 0.75, 0.6)),
                            "roof.png": lambda p: texture(p, 4, (0.55, 0.2, 0.15)),
                            "annex.png": lambda p: texture(p, 13, (0.72, 0.7, 0.62)),
                            "chimney.png": lambda p: texture(p, 14, (0.6, 0.3, 0.22)),
                            "window.png": lambda p: texture(p, 15, (0.18, 0.2, 0.25), contrast=0.5)}),
        synth_scene={"parameters": house_params,
                     "nodes": [GROUND, frame, true_walls, true_roof] + extras,
                     "synth": dict(PHOTO)},
        variants={"scene_eaves.json": eaves_scene})

    # crate_clutter: the box asset's crate, photographed with a ball and a pole standing in
    # front of it that the model leaves out.
    crate_truth = {"x": 0.12, "y": -0.08, "yaw": 17.0, "w": 0.8, "d": 0.6, "h": 0.5}
    clutter = [
        {"name": "ball", "primitive": {"mesh": "meshes/ball.glb"}, "albedo": "textures/ball.png",
         "transforms": [{"translate": [0.68, -0.62, 0.19]}, {"scale": [0.38, 0.38, 0.38]}]},
        {"name": "pole", "primitive": "cylinder", "albedo": "textures/pole.png",
         "transforms": [{"translate": [-0.62, 0.52, 0]}, {"scale": [0.07, 0.07, 1.3]}]},
    ]
    write_asset("crate_clutter", {
        "parameters": box_parameters(),
        "nodes": [GROUND, BOX_NODE],
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }, crate_truth, ring(9, 3.0, 1.8, [0.0, 0.0, 0.3], jitter=0.15, seed=2),
        dict(ground_tex, **{"box.png": lambda p: texture(p, 2, (0.7, 0.35, 0.25)),
                            "ball.png": poster_texture,
                            "pole.png": lambda p: texture(p, 16, (0.35, 0.45, 0.6))}),
        synth_scene={"parameters": box_parameters(), "nodes": [GROUND, BOX_NODE] + clutter,
                     "synth": dict(PHOTO)},
        meshes={"ball.glb": write_sphere_glb})


def plain_texture(path, top, bottom, size=16):
    """A plain cloth or sky: colour `top` at the top row shading smoothly to `bottom`."""
    rows = []
    for y in range(size):
        t = y / (size - 1)
        c = tuple(int(round(255 * (a + (b - a) * t))) for a, b in zip(top, bottom))
        rows.append([c] * size)
    write_png(path, size, size, rows)


def edge_assets():
    """house_cloth: a house photographed in front of a plain grey cloth, the set-up of a
    model building on a table in a studio. Surface the model grows out over a plain
    background is seen alike by every camera, so photo-consistency cannot charge for it;
    only the silhouette's edges say where the house ends (docs/internals/DECISIONS.md,
    2026-11-27). The model (scene.json) has walls, a roof overhanging them by e and a lower
    wing at the +x end; the photographs (synth.json) also show two chimneys on the ridge.
    The house hangs from its front wall (y is the front wall's position), so that d grows
    the house away from the cameras, as the bias on real photographs does.

    Variants switch one cause of the bias off each: synth_textured_cloth.json (the cloth
    printed with texture: not plain), synth_no_chimneys.json, synth_no_overhang.json with
    truth_no_overhang.json (walls flush with the roof, e = 0; scene_no_overhang.json models
    it so), cameras_dense.json (six more
    cameras high above, so the roof's back and sides are seen by two views or more), and
    synth_sky.json (no cloth: a plain sky and a plain field beyond the ground);
    synth_clean.json switches the three of the truth off at once. Others make the scene
    plainer still: synth_plain_walls.json paints walls and wing a plain colour, as a model
    building's often are, synth_cloth_floor.json lays the cloth over the table the house
    stands on, synth_cloth_floor_plain_walls.json does both."""
    params = {"x": uniform(-0.4, 0.4), "y": uniform(-0.6, 0.1), "yaw": uniform(-30, 30),
              "w": uniform(0.6, 1.4), "d": uniform(0.5, 1.2), "h": uniform(0.3, 0.8),
              "rh": uniform(0.1, 0.6), "e": uniform(0.0, 0.1),
              "wl": uniform(0.2, 0.7), "wh": uniform(0.15, 0.45)}
    truth = {"x": 0.0, "y": -0.25, "yaw": 8.0, "w": 1.0, "d": 0.8, "h": 0.5, "rh": 0.35, "e": 0.04,
             "wl": 0.45, "wh": 0.32}
    # The ground stops at the cloth (y = 1.2): behind it no camera sees.
    ground = {"name": "ground", "primitive": "plane", "albedo": "textures/ground.png",
              "transforms": [{"translate": [0, -0.65, 0]}, {"scale": [5, 3.7, 1]}]}
    frame = {"name": "house", "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]}]}
    walls = {"name": "walls", "parent": "house", "primitive": "box", "albedo": "textures/walls.png",
             "transforms": [{"translate": [0, "d/2", 0]}, {"scale": ["w", "d", "h"]}]}
    roof = {"name": "roof", "parent": "house", "primitive": "prism", "albedo": "textures/roof.png",
            "transforms": [{"translate": [0, "d/2", "h"]}, {"scale": ["w + 2*e", "d + 2*e", "rh"]}]}
    wing = {"name": "wing", "parent": "house", "primitive": "box", "albedo": "textures/wing.png",
            "transforms": [{"translate": ["w/2 + wl/2", "0.3*d", 0]}, {"scale": ["wl", "0.6*d", "wh"]}]}
    wing_roof = {"name": "wing_roof", "parent": "house", "primitive": "prism", "albedo": "textures/roof.png",
                 "transforms": [{"translate": ["w/2 + (wl + e)/2", "0.3*d", "wh"]},
                                {"scale": ["wl + e", "0.6*d + 2*e", 0.12]}]}
    house = [ground, frame, walls, roof, wing, wing_roof]
    chimneys = [{"name": "chimney%d" % k, "parent": "house", "primitive": "box", "albedo": "textures/chimney.png",
                 "transforms": [{"translate": [along, "d/2", "h"]}, {"scale": [0.1, 0.1, "rh + 0.14"]}]}
                for k, along in enumerate((-0.3, 0.28))]
    cloth = {"name": "cloth", "primitive": "box", "albedo": "textures/cloth.png",
             "transforms": [{"translate": [0, 1.21, 0]}, {"scale": [24, 0.02, 4]}]}
    printed = dict(cloth, albedo="textures/cloth_printed.png")
    # No cloth: a plain sky far behind and a plain field around the ground (2 mm below it).
    sky = [{"name": "sky", "primitive": "box", "albedo": "textures/sky.png",
            "transforms": [{"translate": [0, 9, 0]}, {"scale": [24, 0.02, 12]}]},
           {"name": "field", "primitive": "plane", "albedo": "textures/field.png",
            "transforms": [{"translate": [0, 3, -0.002]}, {"scale": [24, 12, 1]}]}]
    # A sun behind the cameras, high: the house's shadow falls behind it, mostly out of view.
    photo = dict(PHOTO, sun=[250, 55], ambient=0.35)
    flush = [dict(n, transforms=[t if "scale" not in t else
                                 {"scale": [c.replace(" + 2*e", "").replace(" + e", "") if isinstance(c, str) else c
                                            for c in t["scale"]]}
                                 for t in n["transforms"]])
             if n["name"] in ("roof", "wing_roof") else n for n in house]
    flush = [dict(n, transforms=[{"translate": ["w/2 + wl/2", "0.3*d", "wh"]}, n["transforms"][1]])
             if n["name"] == "wing_roof" else n for n in flush]

    def synth(nodes):  # the overhang's parameter only where a roof uses it
        used = {k: v for k, v in params.items() if k != "e" or any(re.search(r"\be\b", str(t)) for n in nodes
                                                                            for t in n["transforms"])}
        return {"parameters": used, "nodes": nodes, "synth": photo}

    plain_walls = [dict(n, albedo="textures/plaster.png") if n["name"] in ("walls", "wing") else n for n in house]
    # The cloth laid over the table too: the ground the model stands on is as plain as the backdrop.
    on_cloth = lambda nodes: [dict(n, albedo="textures/cloth_floor.png") if n["name"] == "ground" else n for n in nodes]
    cameras = ring(6, 2.5, 1.15, [0.2, 0.1, 0.35], start_deg=210, span_deg=120, jitter=0.1, seed=21)
    high = ring(6, 2.2, 3.2, [0.2, 0.2, 0.4], start_deg=210, span_deg=120, jitter=0.1, seed=22)
    for k, cam in enumerate(high):
        cam["name"], cam["image"] = "cam%d" % (k + 6), "cam%d.png" % (k + 6)
    small = lambda seed, base: (lambda p: texture(p, seed, base, size=64))
    # The model without the overhang, for `vkrecon compare` (docs/internals/EVIDENCE.md).
    no_overhang = {"parameters": {k: v for k, v in params.items() if k != "e"}, "nodes": flush,
                   "likelihood": dict(LIKELIHOOD), "sampler": dict(SAMPLER)}
    write_asset("house_cloth", {
        "parameters": params,
        "nodes": house,
        "likelihood": dict(LIKELIHOOD),
        "sampler": dict(SAMPLER),
    }, truth, cameras,
        {"ground.png": lambda p: texture(p, 1, (0.45, 0.42, 0.35)),
         "walls.png": small(3, (0.8, 0.75, 0.6)),
         "roof.png": small(4, (0.55, 0.2, 0.15)),
         "wing.png": small(13, (0.72, 0.7, 0.62)),
         "chimney.png": small(14, (0.6, 0.3, 0.22)),
         "cloth.png": lambda p: plain_texture(p, (0.62, 0.62, 0.6), (0.5, 0.5, 0.49)),
         "cloth_printed.png": small(17, (0.56, 0.56, 0.55)),
         "sky.png": lambda p: plain_texture(p, (0.62, 0.7, 0.82), (0.78, 0.82, 0.86)),
         "field.png": lambda p: plain_texture(p, (0.5, 0.52, 0.42), (0.5, 0.52, 0.42)),
         "plaster.png": lambda p: plain_texture(p, (0.86, 0.83, 0.74), (0.86, 0.83, 0.74)),
         "cloth_floor.png": lambda p: plain_texture(p, (0.5, 0.5, 0.49), (0.56, 0.56, 0.55))},
        synth_scene=synth(house + chimneys + [cloth]),
        variants={"synth_textured_cloth.json": synth(house + chimneys + [printed]),
                  "synth_no_chimneys.json": synth(house + [cloth]),
                  "synth_no_overhang.json": synth(flush + chimneys + [cloth]),
                  "synth_sky.json": synth(house + chimneys + sky),
                  "synth_clean.json": synth(flush + [printed]),
                  "synth_plain_walls.json": synth(plain_walls + chimneys + [cloth]),
                  "synth_cloth_floor.json": synth(on_cloth(house) + chimneys + [cloth]),
                  "synth_cloth_floor_plain_walls.json": synth(on_cloth(plain_walls) + chimneys + [cloth]),
                  "scene_no_overhang.json": no_overhang})
    folder = os.path.join(HERE, "house_cloth")
    for file, body in (("truth_no_overhang.json", dict(truth, e=0.0)),
                       ("cameras_dense.json", {"cameras": cameras + high})):
        with open(os.path.join(folder, file), "w") as f:
            json.dump(body, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
