#!/usr/bin/python3
"""Draws the figures of docs/guide/OWN_PHOTOGRAPHS.md from the tutorial's own outputs.

    scripts/own_photographs_figures.py out/merton docs/figures [RUN]

Reads WORK/photos; WORK/scene (init's cameras.json, points.ply, scene.json); WORK/preview and
WORK/preview_roofs (the overlays before and after the edit); WORK/RUN (default run: the fit's
overlays and its report); WORK/views (`vkrecon render --orbit 8` of the fitted model). Writes
own_photographs_*.jpg (photographs) and *.png (a plot, a page) into FIGURES.
"""
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402


def save(image, out):
    """Photographs as JPEG (a tenth of the PNG's size), plots and pages as PNG."""
    if out.suffix == ".jpg":
        image.save(out, quality=85, optimize=True)
    else:
        image.save(out, optimize=True)


def strip(paths, out, width=340, box=None):
    """The images (cropped to `box`) side by side, each `width` px wide."""
    images = [Image.open(p).convert("RGB") for p in paths]
    images = [im.crop(box) if box else im for im in images]
    images = [im.resize((width, round(im.height * width / im.width)), Image.LANCZOS) for im in images]
    gap = 6
    canvas = Image.new("RGB", (len(images) * width + (len(images) - 1) * gap, max(im.height for im in images)), "white")
    for i, im in enumerate(images):
        canvas.paste(im, (i * (width + gap), 0))
    save(canvas, out)


def read_ply(path):
    text = Path(path).read_text()
    body = text.split("end_header\n", 1)[1].split()
    values = np.array(body, dtype=float).reshape(-1, 6)
    return values[:, :3], values[:, 3:] / 255.0


def value(parameter):
    return parameter["init"]


def top_view(scene_dir, out):
    """init's frame from above: the points (coloured as photographed), the cameras, and the
    corner template's walls at their starting values."""
    xyz, rgb = read_ply(scene_dir / "points.ply")
    cameras = json.loads((scene_dir / "cameras.json").read_text())["cameras"]
    scene = json.loads((scene_dir / "scene.json").read_text())
    p = {name: value(v) for name, v in scene["parameters"].items()}
    lengths = {n["name"]: n["transforms"][-1]["scale"][0] for n in scene["nodes"] if n["name"] in ("wall_a", "wall_b")}
    fig, ax = plt.subplots(figsize=(5.6, 5.6), dpi=100)
    keep = (xyz[:, 2] > -1.0) & (np.abs(xyz[:, 0]) < 40) & (np.abs(xyz[:, 1]) < 40)
    ax.scatter(xyz[keep, 0], xyz[keep, 1], s=2, c=rgb[keep], linewidths=0)
    lowest = np.inf
    for c in cameras:
        R, t = np.array(c["R"]), np.array(c["t"])
        centre = -R.T @ t
        lowest = min(lowest, centre[1])
        forward = R.T @ np.array([0.0, 0.0, 1.0])
        ax.plot(centre[0], centre[1], "^", color="crimson")
        ax.annotate(c["name"], centre[:2], textcoords="offset points", xytext=(6, -10), fontsize=8)
        ax.arrow(centre[0], centre[1], 4 * forward[0], 4 * forward[1], head_width=0.6, color="crimson")
    corner = np.array([p["xc"], p["yc"]])
    for name, turn in (("wall_a", 0.0), ("wall_b", p["angle"])):
        a = math.radians(p["yaw"] + turn)
        end = corner + lengths[name] * np.array([math.cos(a), math.sin(a)])
        ax.plot([corner[0], end[0]], [corner[1], end[1]], color="gold", linewidth=2.5, label=name if turn == 0 else None)
        ax.annotate(name, end, textcoords="offset points", xytext=(4, 4), fontsize=9)
    ax.plot(*corner, "o", color="gold")
    ax.set_aspect("equal")
    ax.set_xlim(corner[0] - 22, corner[0] + 22)
    ax.set_ylim(lowest - 6, corner[1] + 10)
    ax.set_xlabel("x (COLMAP's units)")
    ax.set_ylabel("y")
    ax.set_title("points.ply from above: the cameras and\nthe corner template's walls at their starting values", fontsize=10)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def crop(path, out, box=None, width=640):
    im = Image.open(path).convert("RGB")
    if box:
        im = im.crop(box)
    save(im.resize((width, round(im.height * width / im.width)), Image.LANCZOS), out)


# Where the walls meet in the 1024 × 768 photographs, large enough to see the wireframe.
CORNER = (160, 0, 864, 560)


def main():
    work, figures = Path(sys.argv[1]), Path(sys.argv[2])
    run = work / (sys.argv[3] if len(sys.argv) > 3 else "run")
    figures.mkdir(parents=True, exist_ok=True)
    strip(sorted((work / "photos").glob("*.jpg")), figures / "own_photographs_photos.jpg")
    top_view(work / "scene", figures / "own_photographs_init.png")
    strip([work / "preview/overlays/002.png", work / "preview_roofs/overlays/002.png"],
          figures / "own_photographs_preview.jpg", width=480, box=CORNER)
    strip([run / "overlays/001.png", run / "overlays/003.png"], figures / "own_photographs_fit.jpg", width=480, box=CORNER)
    with tempfile.TemporaryDirectory() as tmp:  # the report's top: the verdict and the parameters
        shot = Path(tmp) / "report.png"
        subprocess.run([str(Path(__file__).parent / "report_screenshot.sh"), str(run / "report.html"), str(shot)], check=True)
        crop(shot, figures / "own_photographs_report.png", box=(0, 0, 1280, 1130), width=800)
    # Of `render --orbit 8`'s views, 006 looks into the corner from the lawn.
    crop(work / "views/006.png", figures / "own_photographs_view.jpg")


if __name__ == "__main__":
    main()
