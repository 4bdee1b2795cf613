#!/usr/bin/env python3
"""Accuracy and coverage of `vkrecon run` against image noise (thesis Fig 4.15).

For every asset and noise level σ the study renders reference images of the asset at its
truth with `vkrecon synth --noise σ`, reconstructs them with `vkrecon run`, and compares the
MAP and the 95 % intervals of map.json with truth.json. It writes

  WORK/ASSET/sigmaσ/{images,run,record.json}   the runs themselves
  WORK/noise_study.json                         every number of the study
  REPORT (Markdown, also on stdout)             tables, coverage, the accuracy bars
  PLOT (SVG)                                    relative error against σ, one line per asset

Usage (normally through scripts/noise_study.sh, which builds vkrecon first):
  scripts/noise_study.sh                                   # full study, ~40 min on 2 cores
  scripts/noise_study.sh --assets box,house --sigmas 0,16
  scripts/noise_study.sh --quick --assets box --sigmas 0,16 --work /tmp/ns --report /tmp/ns/r.md --plot /tmp/ns/p.svg
  scripts/noise_study.sh --reuse                           # resume an interrupted study
  scripts/noise_study.sh --assets house_annex --scene scene_eaves.json --sigmas 8   # a variant scene

Python 3 standard library only. The binary is $VKRECON (default build/apps/vkrecon).
Exit status: 0 the study ran and the report is written (whatever the bars say), 2 bad
arguments or assets (one line), 1 anything else.
"""

import argparse
import datetime
import json
import math
import os
import resource
import shlex
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path
from xml.sax.saxutils import escape

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_ASSETS = ["box", "house", "stairs", "poster"]
DEFAULT_SIGMAS = [0.0, 8.0, 16.0, 32.0]
QUICK_SETS = ["likelihood.atlas=128", "sampler.iterations=60"]
QUICK_SCALE = 0.25

# The accuracy bars: at noise σ the median over parameters of |MAP − truth| / prior width
# must be at most this, for every asset; coverage and wall time over the same runs.
ERROR_BARS = {0.0: 0.01, 16.0: 0.02, 32.0: 0.04}
COVERAGE_BAR = 0.80
WALL_BAR_S = 300.0


class UsageError(Exception):
    """Bad arguments or assets: one line on stderr, exit 2."""


# ----------------------------------------------------------------------------- arguments

class OneLineParser(argparse.ArgumentParser):
    """argparse prints the usage block on an error; the project's contract is one line."""

    def error(self, message):
        raise UsageError(message)


def parse_args(argv):
    prog = os.environ.get("NOISE_STUDY_PROG", "noise_study.py")
    p = OneLineParser(
        prog=prog, formatter_class=argparse.RawDescriptionHelpFormatter,
        description=__doc__,
        epilog="Relative paths are taken from the repository root (the wrapper runs there).\n"
               "The bars checked: median relative error ≤ 1 %, 2 %, 4 % at σ = 0, 16, 32 for\n"
               "every asset; truth inside the 95 % interval for ≥ 80 % of parameters over\n"
               "those runs; every run ≤ 5 min wall clock.")
    p.add_argument("--assets", default=",".join(DEFAULT_ASSETS),
                   help="comma-separated folders under assets/ (default %(default)s)")
    p.add_argument("--sigmas", default=",".join(f"{s:g}" for s in DEFAULT_SIGMAS),
                   help="comma-separated noise sd on the 0-255 scale (default %(default)s)")
    p.add_argument("--scene", default="scene.json", metavar="FILE",
                   help="the scene file reconstructed, in each asset's folder (default %(default)s; "
                        "e.g. house_annex's scene_eaves.json); the photographs stay the asset's")
    p.add_argument("--seed", type=int, default=1, help="noise seed for synth (default 1)")
    p.add_argument("--scale", type=float, help="image size factor for synth (default: full size)")
    p.add_argument("--likelihood-sigma", default="auto", metavar="auto|given|NUMBER",
                   help="likelihood.sigma passed to run: 'auto' (the run estimates it), "
                        "'given' (max(σ, 1), the true noise) or a number (default auto)")
    p.add_argument("--set", action="append", default=[], metavar="K=V", dest="sets",
                   help="extra override passed to run (repeatable; after --quick's)")
    p.add_argument("--distortion", metavar="SPEC",
                   help="photograph through this lens (synth --distortion SPEC --colmap, e.g. "
                        "OPENCV:k1=-0.12,k2=0.03) and read the cameras through that COLMAP model")
    p.add_argument("--quick", action="store_true",
                   help=f"smoke test: --scale {QUICK_SCALE:g} " + " ".join(f"--set {s}" for s in QUICK_SETS))
    p.add_argument("--reuse", action="store_true",
                   help="skip a run whose map.json exists (made by the same commands), to resume a study")
    p.add_argument("--work", default="out/noise_study", help="work folder (default %(default)s)")
    p.add_argument("--report", default="docs/internals/NOISE_STUDY.md", help="Markdown report (default %(default)s)")
    p.add_argument("--plot", default="docs/figures/noise_study.svg", help="SVG figure (default %(default)s)")
    args = p.parse_args(argv)

    args.assets = split_list(args.assets, "--assets")
    if len(set(args.assets)) != len(args.assets):
        raise UsageError("--assets: an asset is repeated")
    if args.seed < 0:
        raise UsageError(f"--seed: must be ≥ 0, got {args.seed}")
    args.sigmas = [parse_sigma(s) for s in split_list(args.sigmas, "--sigmas")]
    if len(set(args.sigmas)) != len(args.sigmas):
        raise UsageError("--sigmas: a value is repeated")
    if args.likelihood_sigma not in ("auto", "given"):
        try:
            if not (float(args.likelihood_sigma) > 0 and math.isfinite(float(args.likelihood_sigma))):
                raise ValueError
        except ValueError:
            raise UsageError(f"--likelihood-sigma: expected auto, given or a positive number, got '{args.likelihood_sigma}'")
    for s in args.sets:
        if "=" not in s or s.startswith("="):
            raise UsageError(f"--set: expected KEY=VALUE, got '{s}'")
    if args.quick:
        args.sets = QUICK_SETS + args.sets  # the user's later --set wins
        if args.scale is None:
            args.scale = QUICK_SCALE
    if args.scale is not None and not args.scale > 0:
        raise UsageError(f"--scale: must be positive, got {args.scale:g}")
    return args


def split_list(text, option):
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise UsageError(f"{option}: empty list")
    return items


def parse_sigma(text):
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"--sigmas: '{text}' is not a number")
    if not (value >= 0 and math.isfinite(value)):
        raise UsageError(f"--sigmas: {text} must be a finite number ≥ 0")
    return value


def fmt_sigma(sigma):
    return f"{sigma:g}"


# ----------------------------------------------------------------------------- assets

def load_asset(name, scene_file="scene.json"):
    """Truth and prior widths of one asset; a width makes errors comparable across parameters."""
    folder = ROOT / "assets" / name
    scene_path, truth_path = folder / scene_file, folder / "truth.json"
    for path, option in ((folder / "scene.json", "--assets"), (truth_path, "--assets"), (scene_path, "--scene")):
        if not path.is_file():
            raise UsageError(f"{option}: {path.relative_to(ROOT)} does not exist")
    scene, truth = read_json(scene_path), read_json(truth_path)
    widths = {k: prior_width(scene_path, k, v.get("prior", {}))
              for k, v in scene.get("parameters", {}).items()}
    # The clutter assets photograph a truer scene than the model (assets/make_assets.py).
    synth_path = folder / "synth.json" if (folder / "synth.json").is_file() else folder / "scene.json"
    return {"name": name, "scene": scene_path, "synth_scene": synth_path, "truth_path": truth_path,
            "truth": truth, "widths": widths}


def prior_width(path, name, prior):
    if "uniform" in prior:
        lo, hi = prior["uniform"]
        return float(hi) - float(lo)
    if "normal" in prior:
        return 4.0 * float(prior["normal"][1])  # ±2 sd holds 95 %, comparable to a uniform range
    raise UsageError(f"{path}: parameters.{name}.prior: neither uniform nor normal")


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise UsageError(f"{path}: {e}")


# ----------------------------------------------------------------------------- running

def likelihood_sigma(mode, sigma):
    if mode == "auto":
        return "auto"
    if mode == "given":
        return f"{max(sigma, 1.0):g}"  # σ = 0 would make the likelihood infinitely sharp
    return mode


def commands(vkrecon, asset, sigma, args, folder):
    """The synth and run command lines of one (asset, σ), as argument lists."""
    images, run = folder / "images", folder / "run"
    synth = [vkrecon, "synth", rel(asset["synth_scene"]), "--at", rel(asset["truth_path"]),
             "--noise", fmt_sigma(sigma), "--seed", str(args.seed), "-o", rel(images), "--quiet"]
    if args.scale is not None:
        synth += ["--scale", f"{args.scale:g}"]
    cameras = rel(images / "cameras.json")
    if args.distortion:  # a COLMAP object's folder resolves against the scene file: absolute
        synth += ["--distortion", args.distortion, "--colmap"]
        cameras = json.dumps({"colmap": str((images / "sparse").resolve())})
    sets = [f"images={rel(images)}", f"cameras={cameras}",
            f"likelihood.sigma={likelihood_sigma(args.likelihood_sigma, sigma)}"] + args.sets
    run_cmd = [vkrecon, "run", rel(asset["scene"])]
    for s in sets:
        run_cmd += ["--set", s]
    run_cmd += ["-o", rel(run), "--quiet"]
    return synth, run_cmd


def rel(path):
    """Paths in commands and reports relative to the root where possible: shorter, portable."""
    try:
        return str(Path(path).resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def run_one(vkrecon, asset, sigma, args, work, head, source):
    """Synthesises and reconstructs one (asset, σ); returns the record of what happened.
    `head` starts its progress line; `source` (the commit) is kept with the record because a
    reused run may come from an older binary."""
    folder = work / asset["name"] / f"sigma{fmt_sigma(sigma)}"
    synth_cmd, run_cmd = commands(vkrecon, asset, sigma, args, folder)
    if args.reuse:
        record = reusable_record(folder, synth_cmd, run_cmd)
        if record is not None:
            progress(f"{head}: reusing {rel(folder / 'run' / 'map.json')}")
            if record.get("source") not in (None, source):
                record["note"] = f"reused a run made by {record['source']}"
            return record

    # A stale map.json must never stand in for a run that failed this time.
    shutil.rmtree(folder / "run", ignore_errors=True)
    progress(f"{head}: running…")
    record = {"synth_cmd": synth_cmd, "run_cmd": run_cmd, "synth_exit": None, "exit": None,
              "wall_s": None, "cpu_s": None, "stderr_tail": "", "reused": False, "source": source}
    synth = subprocess.run(synth_cmd, cwd=ROOT, capture_output=True, text=True)
    record["synth_exit"] = synth.returncode
    if synth.returncode != 0:
        record["stderr_tail"] = tail(synth.stderr)
    else:
        record.update(timed_run(run_cmd))
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "record.json").write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    return record


def reusable_record(folder, synth_cmd, run_cmd):
    """The record of a finished run made by the same commands, or None to run it again.
    A map.json without record.json (a run made by hand) is taken as it is."""
    map_path, record_path = folder / "run" / "map.json", folder / "record.json"
    if not map_path.is_file():
        return None
    if not record_path.is_file():
        return {"synth_cmd": synth_cmd, "run_cmd": run_cmd, "synth_exit": None, "exit": None,
                "wall_s": None, "cpu_s": None, "stderr_tail": "", "reused": True,
                "source": None, "note": "reused without record.json: exit status and time unknown"}
    old = read_json(record_path)
    if old.get("synth_cmd") != synth_cmd or old.get("run_cmd") != run_cmd:
        progress(f"      {rel(map_path)} was made with other settings: running again")
        return None
    return {**old, "reused": True}


def timed_run(cmd):
    """Wall clock and CPU time (the latter barely moves when others load the cores)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"exit": proc.returncode, "wall_s": wall, "cpu_s": cpu, "stderr_tail": tail(proc.stderr)}


def tail(text, lines=20):
    return "\n".join(text.strip().splitlines()[-lines:])


# ----------------------------------------------------------------------------- scoring

def score(asset, sigma, record, map_path):
    """Per-parameter relative error and coverage of one run, plus its summary numbers."""
    result = {"asset": asset["name"], "sigma": sigma, **record, "parameters": {}, "notes": []}
    if record.get("note"):
        result["notes"].append(record["note"])
    if not map_path.is_file():
        result["notes"].append("no map.json")
        return summarise(result)
    m = read_json(map_path)
    settings = m.get("settings", {})
    result["likelihood_settings"] = settings.get("likelihood", {})
    result["calibration"] = m.get("calibration") or {}
    result["device"] = settings.get("device")
    result["diagnosis"] = m.get("diagnosis") or {}
    # The local search before sampling (sampler.start_search): whether its mode became the MAP.
    start = m.get("start_search") or {}
    result["start_adopted"] = start.get("adopted") if start.get("evaluations") else None
    noise_from_map(result, record)
    for name, est in m.get("parameters", {}).items():
        if name not in asset["truth"] or name not in asset["widths"]:
            result["notes"].append(f"{name}: no truth or prior, not scored")
            continue
        truth, width = float(asset["truth"][name]), asset["widths"][name]
        result["parameters"][name] = {
            "truth": truth, "width": width, **est,
            "rel_error": abs(est["map"] - truth) / width,
            "covered": est["q025"] <= truth <= est["q975"]}
    for name in asset["truth"]:
        if name not in m.get("parameters", {}):
            result["notes"].append(f"{name}: missing from map.json")
    return summarise(result)


def noise_from_map(result, record):
    """The σ the run used: its calibration's when it has one (σ estimated by `auto`, and the
    correlation factor κ), else the settings'. An `auto` that left no trace is worth a note."""
    cal = result["calibration"]
    result["likelihood_sigma_used"] = cal.get("sigma", result["likelihood_settings"].get("sigma"))
    result["sigma_estimated"] = bool(cal.get("sigma_estimated", False))
    result["kappa"] = cal.get("kappa")
    result["chi2_per_dof"] = result.get("diagnosis", {}).get("chi2_per_dof", cal.get("chi2_per_dof"))
    if "likelihood.sigma=auto" in record["run_cmd"] and not result["sigma_estimated"]:
        result["notes"].append("likelihood.sigma=auto, but map.json reports no estimated σ "
                               f"(σ used: {result['likelihood_sigma_used']})")


def summarise(result):
    params = result["parameters"].values()
    errors = [p["rel_error"] for p in params]
    rhats = [p["rhat"] for p in params if p.get("rhat") is not None]
    result["median_rel_error"] = statistics.median(errors) if errors else None
    result["max_rel_error"] = max(errors) if errors else None
    result["covered"] = sum(p["covered"] for p in params)
    result["total"] = len(errors)
    result["max_rhat"] = max(rhats) if rhats else None
    return result


def check_bars(runs, sigmas):
    """The three accuracy bars, each PASS, FAIL or NOT MEASURED with the numbers behind it."""
    bars = []
    for sigma, bar in ERROR_BARS.items():
        at = [r for r in runs if r["sigma"] == sigma]
        name = f"median relative error at σ = {fmt_sigma(sigma)} ≤ {100 * bar:g} % for every asset"
        if not at:
            bars.append({"bar": name, "verdict": "NOT MEASURED", "measured": "σ not in the study"})
            continue
        worst = max(at, key=lambda r: math.inf if r["median_rel_error"] is None else r["median_rel_error"])
        ok = all(r["median_rel_error"] is not None and r["median_rel_error"] <= bar for r in at)
        measured = "no estimate" if worst["median_rel_error"] is None else pct(worst["median_rel_error"])
        bars.append({"bar": name, "verdict": "PASS" if ok else "FAIL",
                     "measured": f"worst {worst['asset']}: {measured}"})

    at = [r for r in runs if r["sigma"] in ERROR_BARS]
    covered, total = sum(r["covered"] for r in at), sum(r["total"] for r in at)
    name = f"truth inside the 95 % interval for ≥ {100 * COVERAGE_BAR:g} % of parameters (σ ∈ {{0, 16, 32}})"
    if total == 0:
        bars.append({"bar": name, "verdict": "NOT MEASURED", "measured": "no scored run at those σ"})
    else:
        bars.append({"bar": name, "verdict": "PASS" if covered / total >= COVERAGE_BAR else "FAIL",
                     "measured": f"{covered}/{total} = {share(covered, total)}"})

    # Only a run that produced an estimate finished; a rejected input says nothing of speed.
    finished = [r for r in runs if r["total"]]
    walls = [r["wall_s"] for r in finished if r["wall_s"] is not None]
    name = f"every run finishes in ≤ {WALL_BAR_S / 60:.0f} min"
    if not walls:
        bars.append({"bar": name, "verdict": "NOT MEASURED", "measured": "no timed run with an estimate"})
    else:
        ok = len(walls) == len(runs) and max(walls) <= WALL_BAR_S
        missing = len(runs) - len(walls)
        bars.append({"bar": name, "verdict": "PASS" if ok else "FAIL",
                     "measured": f"longest {max(walls):.0f} s"
                                 + (f" ({missing} without an estimate or a time)" if missing else "")})
    return bars


# ----------------------------------------------------------------------------- report

def pct(value):
    return "–" if value is None else f"{100 * value:.2f} %"


def share(part, whole):
    return f"{100 * part / whole:.0f} %" if whole else "–"


def num(value, spec):
    return "–" if value is None else format(value, spec)


def sigma_used(r):
    text = num(r.get("likelihood_sigma_used"), ".3g")
    return text + " (est.)" if r.get("sigma_estimated") else text


def map_source(r):
    """Where the MAP came from: the chains, or the local search before sampling whose mode
    scored higher at the end (map.json `start_search.adopted`)."""
    adopted = r.get("start_adopted")
    return "–" if adopted is None else ("local search" if adopted else "chains")


def exit_text(r):
    if r["synth_exit"] not in (0, None):
        return f"synth {r['synth_exit']}"
    text = "?" if r["exit"] is None else str(r["exit"])
    return text + (" (reused)" if r.get("reused") else "")


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def report(study, runs, bars, report_path, plot_path):
    s = study
    out = ["# Noise study: accuracy and coverage against image noise (thesis Fig 4.15)", ""]
    out += [f"- **Command**: `{s['command']}`",
            f"- **Date**: {s['date']}",
            f"- **Source**: {s['source']}",
            f"- **Devices** (`vkrecon devices`): {'; '.join(s['devices']) or '?'}",
            f"- **Device used** (map.json): {s['device_used'] or '?'}",
            f"- **Load** (/proc/loadavg, {os.cpu_count()} cores): before `{s['load_before']}`, after `{s['load_after']}`",
            f"- **Settings**: seed {s['seed']}, scale {s['scale'] or 'full size'}, "
            f"likelihood.sigma {s['likelihood_sigma']}, extra overrides "
            f"{', '.join('`' + x + '`' for x in s['sets']) or 'none'}", ""]
    if s["sets"] or s["scale"]:
        out += ["> Smaller images or changed run settings: these numbers are a smoke test, "
                "not the configuration the accuracy bars are meant for.", ""]
    out += ["Relative error = |MAP − truth| / prior width (uniform: hi − lo; normal: 4 sd). "
            "Covered = truth inside [q025, q975]. Likelihood σ (est. = estimated by `auto`), the "
            "texel correlation factor κ and χ²/dof are the run's own (map.json `calibration`, "
            "`settings`, `diagnosis`): χ²/dof near 1 means σ matches the images' noise. "
            "MAP from: the chains', or the local search's before sampling where its mode scored "
            "higher at the end (map.json `start_search`; – where there was none).", ""]
    out += [f"![relative error against noise]({os.path.relpath(plot_path, report_path.parent)})", ""]
    out += ["## Runs", "", md_table(
        ["asset", "σ", "likelihood σ", "κ", "χ²/dof", "wall s", "CPU s", "median rel. error", "max rel. error",
         "covered", "max R-hat", "MAP from", "exit"],
        [[r["asset"], fmt_sigma(r["sigma"]), sigma_used(r), num(r.get("kappa"), ".2f"),
          num(r.get("chi2_per_dof"), ".3f"),
          num(r["wall_s"], ".1f"), num(r["cpu_s"], ".1f"), pct(r["median_rel_error"]),
          pct(r["max_rel_error"]), f"{r['covered']}/{r['total']}", num(r["max_rhat"], ".3f"),
          map_source(r), exit_text(r)] for r in runs]), ""]
    out += median_table(runs, s["assets"], s["sigmas"])
    out += coverage_section(runs, s["sigmas"])
    out += ["## Bars", "", md_table(["bar", "measured", "verdict"],
                                    [[b["bar"], b["measured"], f"**{b['verdict']}**"] for b in bars]), ""]
    out += parameter_table(runs)
    out += problems_section(runs)
    return "\n".join(out)


def median_table(runs, assets, sigmas):
    by = {(r["asset"], r["sigma"]): r["median_rel_error"] for r in runs}
    rows = []
    for sigma in sigmas:
        values = [by.get((a, sigma)) for a in assets]
        known = [v for v in values if v is not None]
        rows.append([fmt_sigma(sigma)] + [pct(v) for v in values]
                    + [pct(statistics.median(known)) if known else "–"])
    return ["## Median relative error per σ", "",
            "Median over parameters per asset; the last column is the median over assets.", "",
            md_table(["σ"] + assets + ["over assets"], rows), ""]


def coverage_section(runs, sigmas):
    covered, total = sum(r["covered"] for r in runs), sum(r["total"] for r in runs)
    rows = []
    for sigma in sigmas:
        at = [r for r in runs if r["sigma"] == sigma]
        c, t = sum(r["covered"] for r in at), sum(r["total"] for r in at)
        rows.append([fmt_sigma(sigma), f"{c}/{t}", share(c, t)])
    overall = f"{covered}/{total} = {share(covered, total)}"
    return ["## Coverage of the 95 % intervals", "", f"Overall: **{overall}** of parameters.", "",
            md_table(["σ", "covered", "share"], rows), ""]


def parameter_table(runs):
    rows = []
    for r in runs:
        for name, p in r["parameters"].items():
            rows.append([r["asset"], fmt_sigma(r["sigma"]), name, f"{p['truth']:.4g}",
                         f"{p['map']:.4g}", pct(p["rel_error"]),
                         f"[{p['q025']:.4g}, {p['q975']:.4g}]", "yes" if p["covered"] else "**no**",
                         num(p.get("ess"), ".1f"), num(p.get("rhat"), ".3f")])
    if not rows:
        return ["## Per parameter", "", "No run produced an estimate.", ""]
    return ["## Per parameter", "", md_table(
        ["asset", "σ", "parameter", "truth", "MAP", "rel. error", "95 % interval", "covered",
         "ESS", "R-hat"], rows), ""]


def problems_section(runs):
    """Why runs did not exit 0: the run's own last words and its diagnosis."""
    out = []
    for r in runs:
        lines = list(r["notes"])
        if r["exit"] not in (0, None) or r["synth_exit"] not in (0, None):
            lines += [l for l in r["stderr_tail"].splitlines() if l.strip()][-8:]
        if not lines:
            continue
        out += [f"- **{r['asset']} σ={fmt_sigma(r['sigma'])}**, exit {exit_text(r)}:"]
        out += [f"  - `{l.strip()}`" for l in lines]
    return ["## Notes from the runs", ""] + (out or ["None: every run exited 0."]) + [""]


# ----------------------------------------------------------------------------- plot

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"]


def svg_plot(runs, assets, sigmas):
    """Relative error (%, log axis: errors span decades) against σ; a line per asset through
    its medians over parameters, a marker per parameter, the accuracy bars dashed."""
    W, H, left, right, top, bottom = 780, 480, 70, 215, 40, 55
    pw, ph = W - left - right, H - top - bottom
    values = [100 * p["rel_error"] for r in runs for p in r["parameters"].values()]
    values += [100 * b for s, b in ERROR_BARS.items() if s in sigmas]
    positive = [v for v in values if v > 0] or [1.0]
    lo_exp = max(-3, min(-1, math.floor(math.log10(min(positive)))))
    hi_exp = max(1, math.ceil(math.log10(max(positive))))
    floor = 10.0 ** lo_exp  # zero and tinier errors sit on the floor
    smax = max(sigmas) or 1.0

    def x(sigma, offset=0.0):  # 6 % padding keeps markers off the frame
        return left + pw * (0.06 + 0.88 * sigma / smax) + offset

    def y(percent):
        v = math.log10(max(percent, floor))
        return top + ph * (hi_exp - v) / (hi_exp - lo_exp)

    e = []
    e.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="white" stroke="#444"/>')
    for k in range(lo_exp, hi_exp + 1):  # decade grid and labels
        yy = y(10.0 ** k)
        e.append(f'<line x1="{left}" y1="{yy:.1f}" x2="{left + pw}" y2="{yy:.1f}" stroke="#ddd"/>')
        e.append(f'<text x="{left - 6}" y="{yy + 4:.1f}" text-anchor="end">{10.0 ** k:g}</text>')
        for m in range(2, 10):
            if k < hi_exp:
                ym = y(m * 10.0 ** k)
                e.append(f'<line x1="{left}" y1="{ym:.1f}" x2="{left + 4}" y2="{ym:.1f}" stroke="#444"/>')
    for s in sigmas:
        xx = x(s)
        e.append(f'<line x1="{xx:.1f}" y1="{top + ph}" x2="{xx:.1f}" y2="{top + ph + 5}" stroke="#444"/>')
        e.append(f'<text x="{xx:.1f}" y="{top + ph + 19}" text-anchor="middle">{fmt_sigma(s)}</text>')
    e.append(f'<text x="{left + pw / 2}" y="{H - 12}" text-anchor="middle">image noise σ (0–255 scale)</text>')
    e.append(f'<text transform="translate(18 {top + ph / 2}) rotate(-90)" text-anchor="middle">'
             f'relative parameter error (% of prior width)</text>')
    e.append(f'<text x="{left + pw / 2}" y="24" text-anchor="middle" font-size="15">'
             f'Reconstruction error against image noise</text>')

    # A bar holds at its own σ only, so each is a short dash there rather than a joined line.
    bar_points = [(s, 100 * b) for s, b in sorted(ERROR_BARS.items()) if s in sigmas]
    for s, v in bar_points:
        e.append(f'<line x1="{x(s) - 24:.1f}" y1="{y(v):.1f}" x2="{x(s) + 24:.1f}" y2="{y(v):.1f}" '
                 f'stroke="#000" stroke-width="1.5" stroke-dasharray="4 3"><title>bar: median ≤ {v:g} %</title></line>')

    n = len(assets)
    for i, asset in enumerate(assets):
        colour, offset = COLOURS[i % len(COLOURS)], (i - (n - 1) / 2) * 7.0  # spread overlaps
        mine = sorted((r for r in runs if r["asset"] == asset and r["parameters"]), key=lambda r: r["sigma"])
        for r in mine:
            for name, p in r["parameters"].items():
                v = 100 * p["rel_error"]
                e.append(f'<circle cx="{x(r["sigma"], offset):.1f}" cy="{y(v):.1f}" r="2.5" fill="{colour}" '
                         f'fill-opacity="0.45"><title>{escape(asset)} σ={fmt_sigma(r["sigma"])} '
                         f'{escape(name)}: {v:.3g} %</title></circle>')
        pts = " ".join(f"{x(r['sigma'], offset):.1f},{y(100 * r['median_rel_error']):.1f}" for r in mine)
        if pts:
            e.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for r in mine:
            e.append(f'<rect x="{x(r["sigma"], offset) - 3.5:.1f}" y="{y(100 * r["median_rel_error"]) - 3.5:.1f}" '
                     f'width="7" height="7" fill="{colour}"><title>{escape(asset)} σ={fmt_sigma(r["sigma"])} '
                     f'median: {100 * r["median_rel_error"]:.3g} %</title></rect>')
    e += svg_legend(assets, left + pw + 15, top + 10, floor, bool(bar_points))
    body = "\n".join("  " + line for line in e)
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" '
            f'font-family="sans-serif" font-size="12">\n'
            f'  <rect width="{W}" height="{H}" fill="white"/>\n{body}\n</svg>\n')


def svg_legend(assets, lx, ly, floor, bars):
    e = []
    for i, asset in enumerate(assets):
        colour, yy = COLOURS[i % len(COLOURS)], ly + 18 * i
        e.append(f'<line x1="{lx}" y1="{yy}" x2="{lx + 22}" y2="{yy}" stroke="{colour}" stroke-width="2"/>')
        e.append(f'<rect x="{lx + 7.5}" y="{yy - 3.5}" width="7" height="7" fill="{colour}"/>')
        e.append(f'<text x="{lx + 30}" y="{yy + 4}">{escape(asset)}</text>')
    yy = ly + 18 * len(assets) + 10
    e.append(f'<rect x="{lx + 7.5}" y="{yy - 3.5}" width="7" height="7" fill="#666"/>')
    e.append(f'<text x="{lx + 30}" y="{yy + 4}">median over parameters</text>')
    e.append(f'<circle cx="{lx + 11}" cy="{yy + 18}" r="2.5" fill="#666" fill-opacity="0.45"/>')
    e.append(f'<text x="{lx + 30}" y="{yy + 22}">one parameter</text>')
    if bars:
        e.append(f'<line x1="{lx}" y1="{yy + 36}" x2="{lx + 22}" y2="{yy + 36}" stroke="#000" stroke-width="1.5" stroke-dasharray="4 3"/>')
        e.append(f'<text x="{lx + 30}" y="{yy + 40}">bar (median ≤)</text>')
    e.append(f'<text x="{lx}" y="{yy + 62}" font-size="10" fill="#666">errors below {floor:g} %</text>')
    e.append(f'<text x="{lx}" y="{yy + 75}" font-size="10" fill="#666">are drawn at {floor:g} %</text>')
    return e


# ----------------------------------------------------------------------------- main

def capture(cmd):
    try:
        return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True).stdout.strip()
    except OSError:
        return ""


def loadavg():
    try:
        return Path("/proc/loadavg").read_text().strip()
    except OSError:
        return "?"


def progress(line):
    print(line, file=sys.stderr, flush=True)


def result_line(r):
    if r["median_rel_error"] is None:
        why = [l for l in r["stderr_tail"].splitlines() if l.strip()][-1:] or r["notes"][:1]
        return f"exit {exit_text(r)}, no estimate" + (f": {why[0].strip()}" if why else "")
    wall = "time unknown" if r["wall_s"] is None else f"{r['wall_s']:.1f} s"
    return (f"exit {exit_text(r)}, {wall}, median error {pct(r['median_rel_error'])}, "
            f"max {pct(r['max_rel_error'])}, covered {r['covered']}/{r['total']}, "
            f"max R-hat {num(r['max_rhat'], '.3f')}")


def main(argv):
    args = parse_args(argv)
    vkrecon = os.environ.get("VKRECON", "build/apps/vkrecon")
    if not (ROOT / vkrecon).is_file() and not Path(vkrecon).is_file():
        raise UsageError(f"{vkrecon}: no vkrecon binary (build it with scripts/build.sh vkrecon)")
    assets = [load_asset(a, args.scene) for a in args.assets]
    work, report_path, plot_path = (ROOT / args.work, ROOT / args.report, ROOT / args.plot)
    prog = os.environ.get("NOISE_STUDY_PROG", "scripts/noise_study.py")
    dirty = capture(["git", "status", "--porcelain", "--untracked-files=no"])
    study = {
        "command": shlex.join([prog] + argv),
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "source": (capture(["git", "rev-parse", "--short", "HEAD"]) or "?")
                  + (" with uncommitted changes" if dirty else ""),
        "devices": capture([vkrecon, "devices"]).splitlines(),
        "load_before": loadavg(), "assets": args.assets, "sigmas": args.sigmas,
        "scene": args.scene, "seed": args.seed, "scale": args.scale, "likelihood_sigma": args.likelihood_sigma,
        "distortion": args.distortion,
        "sets": args.sets, "reuse": args.reuse}

    # Noise level outermost: an interrupted study (resumed with --reuse) has every asset
    # at the first levels rather than some assets at every level.
    runs, jobs = [], [(a, s) for s in args.sigmas for a in assets]
    for i, (asset, sigma) in enumerate(jobs, 1):
        head = f"[{i}/{len(jobs)}] {asset['name']} σ={fmt_sigma(sigma)}"
        record = run_one(vkrecon, asset, sigma, args, work, head, study["source"])
        folder = work / asset["name"] / f"sigma{fmt_sigma(sigma)}"
        runs.append(score(asset, sigma, record, folder / "run" / "map.json"))
        progress(f"{head}: {result_line(runs[-1])}")
    study["load_after"] = loadavg()
    study["device_used"] = next((r["device"] for r in runs if r.get("device")), None)

    bars = check_bars(runs, args.sigmas)
    work.mkdir(parents=True, exist_ok=True)
    (work / "noise_study.json").write_text(
        json.dumps({"study": study, "runs": runs, "bars": bars}, indent=1) + "\n", encoding="utf-8")
    text = report(study, runs, bars, report_path, plot_path)
    for path, content in ((report_path, text + "\n"), (plot_path, svg_plot(runs, args.assets, args.sigmas))):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(content, encoding="utf-8")
    print(text)
    progress(f"wrote {rel(report_path)}, {rel(plot_path)}, {rel(work / 'noise_study.json')}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except UsageError as e:
        print(f"noise_study: {e}", file=sys.stderr)
        sys.exit(2)
    except KeyboardInterrupt:
        print("noise_study: interrupted; run again with --reuse to go on where it stopped", file=sys.stderr)
        sys.exit(130)
