#!/usr/bin/python3
"""A fit of the photographs tutorial's scene (docs/guide/OWN_PHOTOGRAPHS.md) against the Merton
dataset's own reference, in the dataset's units.

    docs/examples/merton/compare_fit.py SCENE_DIR RUN_DIR... [--data DATA_DIR]

SCENE_DIR is `vkrecon init`'s folder (its cameras.json is in COLMAP's units), each RUN_DIR a
`vkrecon run` output of the tutorial's scene. COLMAP's units become the dataset's by the ratio
of the two camera sets' spreads about their centroids; the angle and pitches need no
conversion. DATA_DIR defaults to ../shared/data/merton_college_1 beside the repository.
"""
import argparse
import json
import pathlib

import numpy as np

REFERENCE = "walls 87.6-88.2 deg apart (reference_fits.py), eaves at 4.7-5.2, roofs pitched about 49 and 53 deg"


def centres(cameras):
    return {c["name"].split(".")[0]: -np.array(c["R"]).T @ np.array(c["t"]) for c in cameras}


def main():
    root = pathlib.Path(__file__).resolve().parents[3]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--data", default=str(root.parent / "shared/data/merton_college_1"))
    args = parser.parse_args()
    ours = centres(json.loads((pathlib.Path(args.scene) / "cameras.json").read_text())["cameras"])
    theirs = centres(json.loads((pathlib.Path(args.data) / "cameras.json").read_text())["cameras"])
    names = sorted(set(ours) & set(theirs))
    a = np.array([ours[n] for n in names])
    b = np.array([theirs[n] for n in names])
    scale = np.linalg.norm(b - b.mean(0), axis=1).sum() / np.linalg.norm(a - a.mean(0), axis=1).sum()
    print(f"dataset units per COLMAP unit: {scale:.4f} (from {len(names)} cameras); reference: {REFERENCE}")
    for run in args.runs:
        p = json.loads((pathlib.Path(run) / "map.json").read_text())["parameters"]
        rhat = max(v["rhat"] for v in p.values())

        def show(name, factor=1.0):
            v = p[name]
            return f"{name} {factor * v['map']:.3g} [{factor * v['q025']:.3g}, {factor * v['q975']:.3g}]"

        print(f"{run}: largest R-hat {rhat:.2f}; " + "; ".join([show("angle"), show("h", scale), show("pa"), show("pb")]))


if __name__ == "__main__":
    main()
