#!/usr/bin/env python3
"""Where the likelihood puts a house in front of a plain cloth, and why: the study of
docs/internals/DECISIONS.md, 2026-11-27 ("The evidence at the edges"). For each variant of
assets/house_cloth (one cause of the bias switched off in the photographs each) it
photographs the truth with `vkrecon synth` (quarter size, noise 8, seed 7 or --seed), fits the MAP
with `vkrecon fit` from the truth, scores the truth and the MAP with
`vkrecon likelihood`, and sweeps d, rh and w through the truth. Prints a Markdown table.

    python3 scripts/edge_study.py [--vkrecon build/apps/vkrecon] [--work /tmp/edge_study]
        [--only all,a_off,…] [--sigma 4] [--seed 7]
"""
import argparse
import csv
import io
import json
import math
import os
import subprocess

ASSET = "assets/house_cloth"
# name: (what is switched off, synth scene, truth, cameras photographed)
VARIANTS = {
    "all": ("nothing", "synth.json", "truth.json", "cameras.json"),
    "a_off": ("(a) plain cloth: printed", "synth_textured_cloth.json", "truth.json", "cameras.json"),
    "b_off": ("(b) chimneys", "synth_no_chimneys.json", "truth.json", "cameras.json"),
    "c_off": ("(c) one-view texels: 6 high cameras more", "synth.json", "truth.json", "cameras_dense.json"),
    "d_off": ("(d) overhang", "synth_no_overhang.json", "truth_no_overhang.json", "cameras.json"),
    "clean": ("(a), (b), (d)", "synth_clean.json", "truth_no_overhang.json", "cameras.json"),
    "clean_c": ("(a), (b), (c), (d)", "synth_clean.json", "truth_no_overhang.json", "cameras_dense.json"),
    "sky": ("cloth → plain sky", "synth_sky.json", "truth.json", "cameras.json"),
    "plain_walls": ("nothing; walls plain", "synth_plain_walls.json", "truth.json", "cameras.json"),
    "cloth_floor": ("nothing; cloth on the floor too", "synth_cloth_floor.json", "truth.json", "cameras.json"),
    "cloth_floor_plain_walls": ("nothing; cloth floor, walls plain", "synth_cloth_floor_plain_walls.json",
                                "truth.json", "cameras.json"),
}
SWEEPS = {"d": (0.72, 1.0, 15), "rh": (0.28, 0.42, 15), "w": (0.9, 1.1, 11)}
# The ridge slid back and up along the plane of the front slope (d and rh/(d/2 + e) change
# together, the front wall stays): s is the relative change of d/2 + e.
RIDGE = [k * 0.025 for k in range(-4, 9)]


def run(args, **kw):
    return subprocess.run(args, check=True, capture_output=True, text=True, **kw).stdout


def pitch(p):
    return math.degrees(math.atan2(p["rh"], p["d"] / 2 + p["e"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vkrecon", default="build/apps/vkrecon")
    ap.add_argument("--work", default="/tmp/edge_study")
    ap.add_argument("--only", default=",".join(VARIANTS))
    ap.add_argument("--sigma", default="4")
    ap.add_argument("--seed", default="7", help="the photographs' noise seed")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a scene setting for fit and likelihood, e.g. likelihood.edges=true (repeatable)")
    a = ap.parse_args()
    rows = []
    for name in a.only.split(","):
        what, synth, truth_file, cameras = VARIANTS[name]
        out = os.path.join(a.work, name)
        truth_path = os.path.join(ASSET, truth_file)
        # synth takes only the parameters its scene uses (without an overhang it has no e).
        os.makedirs(out, exist_ok=True)
        used = json.load(open(os.path.join(ASSET, synth)))["parameters"]
        with open(os.path.join(out, "at_synth.json"), "w") as f:
            json.dump({k: v for k, v in json.load(open(truth_path)).items() if k in used}, f)
        run([a.vkrecon, "synth", os.path.join(ASSET, synth), "--at", os.path.join(out, "at_synth.json"),
             "--scale", "0.25", "--noise", "8", "--seed", a.seed, "--set", "cameras=" + os.path.join(ASSET, cameras), "-o", out])
        common = ["--set", "cameras=" + os.path.join(out, "cameras.json"), "--set", "images=" + out,
                  "--set", "likelihood.sigma=" + a.sigma] + [x for kv in a.set for x in ("--set", kv)]
        scene = os.path.join(ASSET, "scene.json")
        truth = json.load(open(truth_path))
        # From the truth: the mode nearest it, not wherever a local method ends from afar.
        start = [x for k, v in truth.items() for x in ("--set", "parameters.%s.init=%r" % (k, v))]
        run([a.vkrecon, "fit", scene, "-o", os.path.join(out, "fit"), "--quiet"] + common + start)
        fit = json.load(open(os.path.join(out, "fit", "map.json")))
        best = {k: v["map"] for k, v in fit["parameters"].items()}

        def score(at):
            table = run([a.vkrecon, "likelihood", scene, "--at", at] + common)
            return {k: float(v) for k, v in (l.split() for l in table.splitlines()) if k in
                    ("total", "log_likelihood", "log_occlusion_prior", "log_edges", "seen_once")}

        at_truth, at_map = score(truth_path), score(os.path.join(out, "fit", "at_map.json"))
        peaks = {}
        for p, (lo, hi, n) in SWEEPS.items():
            text = run([a.vkrecon, "likelihood", scene, "--at", truth_path, "--sweep", "%s=%g:%g:%d" % (p, lo, hi, n)]
                       + common)
            table = list(csv.DictReader(io.StringIO(text)))
            peaks[p] = float(max(table, key=lambda r: float(r["loglik"]))["value"])
        ridge = []
        for k, s in enumerate(RIDGE):
            at = dict(truth)
            half = (truth["d"] / 2 + truth["e"]) * (1 + s)
            at["d"], at["rh"] = 2 * (half - truth["e"]), truth["rh"] * (1 + s)
            path = os.path.join(out, "ridge_%d.json" % k)
            with open(path, "w") as f:
                json.dump(at, f)
            ridge.append((s, score(path)))
        s_best, best_ridge = max(ridge, key=lambda r: r[1]["total"])
        peaks["ridge"] = (s_best, best_ridge["total"] - at_truth["total"],
                          best_ridge["log_occlusion_prior"] - at_truth["log_occlusion_prior"])
        rows.append((name, what, truth, best, at_truth, at_map, peaks))
        print(name, {k: round(v, 4) for k, v in best.items()}, "gain", round(at_map["total"] - at_truth["total"], 1),
              "peaks", peaks, flush=True)

    print()
    print("| variant | switched off | d (MAP, %) | rh (MAP, %) | w (MAP, %) | pitch ° (truth → MAP) | e MAP | "
          "gain of the MAP over the truth (nats): total = photo-consistency (+ edges) + occlusion prior | "
          "one-view texels, truth → MAP | 1-D sweep peaks d / rh / w | ridge back along the front slope: "
          "best s, gain (of it the occlusion prior's) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, what, truth, best, at_truth, at_map, peaks in rows:
        cell = lambda p: "%.3f (%+.1f %%)" % (best[p], 100 * (best[p] / truth[p] - 1))
        gain = lambda k: at_map.get(k, 0.0) - at_truth.get(k, 0.0)
        print("| %s | %s | %s | %s | %s | %.1f → %.1f | %.3f | %+.0f = %+.0f %+.0f | %d → %d | %.2f / %.2f / %.2f "
              "| %+.3f, %+.0f (%+.0f) |" % (
            name, what, cell("d"), cell("rh"), cell("w"), pitch(truth), pitch(best), best["e"], gain("total"),
            gain("log_likelihood") + gain("log_edges"), gain("log_occlusion_prior"), at_truth["seen_once"], at_map["seen_once"],
            peaks["d"], peaks["rh"], peaks["w"], peaks["ridge"][0], peaks["ridge"][1], peaks["ridge"][2]))


if __name__ == "__main__":
    main()
