#!/usr/bin/env python3
"""Profiles of the likelihood through the truth, with and without the edge term.

For each asset it photographs the truth with `vkrecon synth` (quarter size, noise 8, seed 1,
the asset's synth.json where it has one), then sweeps every parameter through its truth with
`vkrecon likelihood --sweep` (±STEPS steps of STEP × the prior's width, the others at the
truth, σ 8), once with `likelihood.edges` false and once true. Prints, per parameter, where
each profile peaks, in steps from the truth: 0 is the truth. docs/internals/LIKELIHOOD.md,
"Edges", quotes it.

    python3 scripts/edge_profiles.py --work /tmp/edge_profiles [--assets box,house]
"""
import argparse
import csv
import io
import json
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
ASSETS = os.path.join(HERE, "..", "assets")


def run(args):
    return subprocess.run(args, check=True, capture_output=True, text=True).stdout


def width(prior):
    if "uniform" in prior:
        lo, hi = prior["uniform"]
        return hi - lo
    return 4 * prior["normal"][1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vkrecon", default=os.path.join(HERE, "..", "build", "apps", "vkrecon"))
    ap.add_argument("--work", default="/tmp/edge_profiles")
    ap.add_argument("--assets", default="box,house,stairs,poster,house_cloth")
    ap.add_argument("--step", type=float, default=0.005, help="sweep step, share of the prior's width")
    ap.add_argument("--steps", type=int, default=4, help="steps either side of the truth")
    a = ap.parse_args()
    print("| asset | parameter | step | peak without edges | peak with edges |")
    print("|---|---|---|---|---|")
    for asset in a.assets.split(","):
        folder = os.path.join(ASSETS, asset)
        out = os.path.join(a.work, asset)
        os.makedirs(out, exist_ok=True)
        synth = os.path.join(folder, "synth.json")
        synth = synth if os.path.isfile(synth) else os.path.join(folder, "scene.json")
        truth_path = os.path.join(folder, "truth.json")
        run([a.vkrecon, "synth", synth, "--at", truth_path, "--scale", "0.25", "--noise", "8", "--seed", "1",
             "-o", out, "-q"])
        scene_path = os.path.join(folder, "scene.json")
        scene, truth = json.load(open(scene_path)), json.load(open(truth_path))
        common = ["--set", "cameras=" + os.path.join(out, "cameras.json"), "--set", "images=" + out,
                  "--set", "likelihood.sigma=8"]
        for name, p in scene["parameters"].items():
            step = a.step * width(p["prior"])
            lo, hi = truth[name] - a.steps * step, truth[name] + a.steps * step
            peaks = []
            for edges in ("false", "true"):
                text = run([a.vkrecon, "likelihood", scene_path, "--at", truth_path, "-q",
                            "--sweep", "%s=%.9g:%.9g:%d" % (name, lo, hi, 2 * a.steps + 1),
                            "--set", "likelihood.edges=" + edges] + common)
                rows = list(csv.DictReader(io.StringIO(text)))
                best = max(range(len(rows)), key=lambda k: float(rows[k]["loglik"]))
                peaks.append(best - a.steps)
            print("| %s | %s | %.4g | %+d | %+d |" % (asset, name, step, peaks[0], peaks[1]), flush=True)


if __name__ == "__main__":
    main()
