#!/usr/bin/env python3
"""The "On a GPU" section of bench/RESULTS.md from what scripts/device_check.sh measured there.

Usage: bench/device_report.py DIR [--results bench/RESULTS.md] [--lavapipe bench/results-llvmpipe-….json]

DIR holds the files `scripts/device_check.sh run` wrote (machine.txt, agree.txt, bench.json,
bench.err, run.txt, run_map.json) and agree_lavapipe.txt, the reference the bundle carried.
Splices the section between <!-- gpu NAME --> and <!-- /gpu NAME --> (appended when missing), as
peers_report.py does for its own, so bench/run.sh, which rewrites the lavapipe sections, keeps
it. The analysis text lives in DIR/notes.md (written by hand after looking at the numbers).
"""

import argparse
import glob
import json
import math
import os
import statistics



def markers(folder):
    """One section per device folder, so several GPUs' sections live side by side."""
    name = os.path.basename(os.path.normpath(folder))
    return f"<!-- gpu {name} -->", f"<!-- /gpu {name} -->"


def read(path, default=""):
    try:
        with open(path) as f:
            return f.read()
    except OSError:
        return default


def likelihood_lines(text):
    """{(asset, point, kind): {field: value}} from `likelihoods` lines of device_check.sh."""
    out = {}
    for line in text.splitlines():
        words = line.split()
        if len(words) < 5:
            continue
        fields = {}
        for k, v in zip(words[3::2], words[4::2]):
            try:
                fields[k] = float(v)
            except ValueError:
                pass
        out[tuple(words[:3])] = fields
    return out


def num(x, digits=2):
    return "—" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:,.{digits}f}"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def agreement(ref, gpu):
    rows = []
    for key in ref:
        asset, point, kind = key
        a, b = ref[key].get("total"), gpu.get(key, {}).get("total")
        diff = None if a is None or b is None else b - a
        rel = None if diff is None or not a else abs(diff / a)
        # The difference the sampler sees: truth minus the moved point, on each device.
        other = (asset, "moved" if point == "truth" else "truth", kind)
        d_ref = d_gpu = None
        if point == "truth" and other in ref and other in gpu:
            d_ref = a - ref[other].get("total", math.nan)
            d_gpu = (b if b is not None else math.nan) - gpu[other].get("total", math.nan)
        rows.append([asset, point, kind, num(a), num(b), num(diff), "—" if rel is None else f"{rel:.1e}",
                     num(d_ref) if point == "truth" else "", num(d_gpu) if point == "truth" else ""])
    return rows


def throughput(gpu_rows, cpu_rows):
    names = ["house", "box", "stairs", "poster", "house/image", "box/image", "house/level1", "house/level2",
             "batch/1", "batch/4", "batch/16", "batch/64", "batch/256", "cameras/32", "atlas/2048",
             "triangles/100110"]
    by_gpu = {r["name"]: r for r in gpu_rows}
    by_cpu = {r["name"]: r for r in cpu_rows}
    rows = []
    for n in names:
        g, c = by_gpu.get(n), by_cpu.get(n)
        if not g or g.get("skipped"):
            continue
        gh, ch = g.get("hypotheses_per_s"), (c or {}).get("hypotheses_per_s")
        gpu_ms = sum((g.get("passes_ms") or {}).values()) or None
        rows.append([f"`{n}`", g.get("batch", "—"), num(gh, 1), num(g.get("wall_ms"), 3), num(gpu_ms, 3),
                     num(ch, 1), "—" if not gh or not ch else f"{gh / ch:.0f}×"])
    return rows


def passes(row):
    total = sum(row["passes_ms"].values())
    return [[p, num(ms, 3), f"{100 * ms / total:.0f} %"] for p, ms in row["passes_ms"].items()]


def run_summary(m, truth, priors):
    s = m.get("sampling", {})
    errs, inside = [], 0
    for name, p in m.get("parameters", {}).items():
        if name in truth and name in priors:
            lo, hi = priors[name]
            errs.append(abs(p["map"] - truth[name]) / (hi - lo))
            inside += p["q025"] <= truth[name] <= p["q975"]
    rows = [["ended by", s.get("ended_by")], ["largest R̂", num(s.get("max_rhat"), 3)],
            ["smallest bulk ESS", num(s.get("min_ess"), 0)], ["iterations", m.get("iterations")],
            ["evaluations", m.get("evaluations")],
            ["median \\|MAP − truth\\| / prior width", f"{100 * statistics.median(errs):.3f} %" if errs else "—"],
            ["largest", f"{100 * max(errs):.3f} %" if errs else "—"],
            ["truths inside their 95 % interval", f"{inside} of {len(errs)}"],
            ["diagnosis", (m.get("diagnosis") or {}).get("verdict")]]
    return rows


def default_runs(text):
    """Rows from the `default ASSET {sampling} key value …` lines of device_check.sh."""
    rows = []
    for line in text.splitlines():
        if not line.startswith("default ") or "{" not in line:
            continue
        head, rest = line.split("{", 1)
        sampling = json.loads("{" + rest[:rest.index("}") + 1])
        words = rest[rest.index("}") + 1:].split()
        at = words.index("covered")
        covered = words[at + 1:at + 3]  # inside, of
        words = words[:at] + words[at + 3:]
        f = dict(zip(words[0::2], words[1::2]))
        rows.append([head.split()[1], sampling["ended_by"], num(sampling["max_rhat"], 3), num(sampling["min_ess"], 0),
                     f["iterations"], f["evaluations"], f"{100 * float(f['median_error']):.3f} %",
                     f"{covered[0]} of {covered[1]}", f["verdict"], f"{f['wall_s']} s"])
    return rows


def merton_runs(text):
    """Rows from the `merton seed N {sampling} key value … NAME MAP [LO,HI] …` lines."""
    rows = []
    for line in text.splitlines():
        if not line.startswith("merton seed ") or "{" not in line:
            continue
        head, rest = line.split("{", 1)
        sampling = json.loads("{" + rest[:rest.index("}") + 1])
        w = rest[rest.index("}") + 1:].split()

        def after(key, n=1):
            i = w.index(key)
            return w[i + 1:i + 1 + n]

        angle, xc = after("angle", 2), after("xc", 2)
        rows.append([head.split()[2], sampling["ended_by"], num(sampling["max_rhat"], 3), num(sampling["min_ess"], 0),
                     num(float(after("log_posterior")[0]), 1), f"{angle[0]}° {angle[1]}", f"{xc[0]} {xc[1]}",
                     after("verdict")[0], f"{after('wall_s')[0]} s"])
    return rows


def section(folder, lavapipe_json):
    machine = read(os.path.join(folder, "machine.txt")).strip().splitlines()
    bench = json.loads(read(os.path.join(folder, "bench.json"), "{}") or "{}")
    device = bench.get("device") or next((l.split(":", 1)[1].strip() for l in machine if l[:1].isdigit()), "?")
    begin, end = markers(folder)
    out = [begin, "", f"## On a GPU: {device}", ""]
    out.append("Measured by `scripts/device_check.sh run OUT` on a lent machine, from the bundle that "
               "`scripts/device_check.sh prepare` made here (one Release binary, lavapipe's results carried for "
               f"comparison); files in `{folder}/`. The machine:")
    out += ["", "```", *machine, "```", ""]
    notes = read(os.path.join(folder, "notes.md")).strip()
    if notes:
        out += [notes, ""]

    ref = likelihood_lines(read(os.path.join(folder, "agree_lavapipe.txt")))
    gpu = likelihood_lines(read(os.path.join(folder, "agree.txt")))
    out += ["### The likelihood on the GPU against lavapipe", "",
            "Each asset's photographs (synthesised here at half size, σ 8, seed 1) scored by the same binary on both "
            "devices (`vkrecon likelihood … --at`), at the truth and at the truth moved by a twentieth of every "
            "prior's width; the last two columns are truth − moved on each device, the difference the sampler "
            "acts on.", ""]
    out += [table(["asset", "point", "kind", "lavapipe", "GPU", "GPU − lavapipe", "relative", "Δ lavapipe",
                   "Δ GPU"], agreement(ref, gpu)), ""]

    if bench.get("rows"):
        cpu_rows = json.loads(read(lavapipe_json, "{}")).get("rows", []) if lavapipe_json else []
        out += ["### Throughput", "",
                f"`vkrecon bench --json`, {num(bench.get('seconds'), 0)} s; lavapipe's column is this file's "
                "own run on the 2-core host (same rows, same settings).", ""]
        out += [table(["row", "K", "GPU hyp/s", "wall ms/hyp", "GPU ms/hyp", "lavapipe hyp/s", "ratio"],
                      throughput(bench["rows"], cpu_rows)), ""]
        house = next((r for r in bench["rows"] if r["name"] == "house"), None)
        if house and house.get("passes_ms"):
            out += ["Where `house`'s GPU time goes:", "", table(["pass", "ms/hyp", "share"], passes(house)), ""]
        k1 = next((r for r in bench["rows"] if r["name"] == "batch/1"), None)
        k16 = next((r for r in bench["rows"] if r["name"] == "batch/16"), None)
        if k1 and k16:
            out += [f"Batching: K = 16 over K = 1 is {k16['hypotheses_per_s'] / k1['hypotheses_per_s']:.2f}× on this "
                    "device (1.00× on lavapipe).", ""]
    else:
        out += ["### Throughput", "", "The bench did not finish: " + read(os.path.join(folder, "bench.err"))[-400:], ""]

    m = json.loads(read(os.path.join(folder, "run_map.json"), "{}") or "{}")
    if m:
        truth = json.load(open("assets/house/truth.json"))
        scene = json.load(open("assets/house/scene.json"))
        priors = {k: v["prior"]["uniform"] for k, v in scene["parameters"].items() if "uniform" in v["prior"]}
        out += ["### One default run of `house`", "",
                "`vkrecon run assets/house/scene.json` with its defaults, on photographs synthesised there at full "
                "size (640×480), σ 16, seed 1:", ""]
        rows = run_summary(m, truth, priors)
        wall = [l for l in read(os.path.join(folder, "run.txt")).splitlines() if l.startswith("wall:")]
        if wall:
            rows.append(["wall clock", wall[-1].split(":", 1)[1].strip()])
        out += [table(["", "value"], rows), ""]
    defaults = default_runs(read(os.path.join(folder, "run.txt")))
    if defaults:
        out += ["### The sampler at its defaults", "",
                "Each asset's scene with its `likelihood` and `sampler` blocks deleted, on photographs synthesised "
                "there at full size, σ 16, seed 1 (`DEVICE_CHECK_DEFAULT_RUNS`; the time limit in `run.txt`):", ""]
        out += [table(["asset", "ended by", "largest R̂", "smallest ESS", "iterations", "evaluations",
                       "median error", "covered", "verdict", "wall"], defaults), ""]
    merton = merton_runs(read(os.path.join(folder, "run.txt")))
    if merton:
        out += ["### Merton, one run per seed", "",
                "`docs/examples/merton/scene.json` as it is (600 iterations), its photographs carried from "
                "`../shared/data` (`DEVICE_CHECK_MERTON_SEEDS`). The log posterior is each run's own, under the "
                "calibration that run estimated, so it ranks the seeds only roughly.", ""]
        out += [table(["seed", "ended by", "largest R̂", "smallest ESS", "log posterior", "angle (95 %)",
                       "xc (95 %)", "verdict", "wall"], merton), ""]
    out.append(end)
    return "\n".join(out)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("folder")
    p.add_argument("--results", default=os.path.join("bench", "RESULTS.md"))
    p.add_argument("--lavapipe", default=next(iter(sorted(glob.glob("bench/results-llvmpipe-*.json"))), None))
    a = p.parse_args()
    text = read(a.results)
    new = section(a.folder, a.lavapipe)
    begin, end = markers(a.folder)
    if begin in text and end in text:
        text = text[:text.index(begin)] + new + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + new + "\n"
    with open(a.results, "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
