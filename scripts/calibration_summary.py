#!/usr/bin/env python3
"""How calibrated a set of noise-study runs' intervals are: z = (MAP − truth) / posterior sd.

A calibrated posterior gives median |z| ≈ 0.67, RMS z ≈ 1 and 95 % intervals that hold the
truth 95 % of the time; intervals too wide give small z and coverage near 100 %.

Where a run's calibration also measured κ from the residuals' correlation
(`calibration.noise_correlation`), z_noise is z with the sd rescaled to that κ,
sd·√(κ_noise/κ), κ the one the run's intervals are stated at: what they would have been had
they been stated at κ_noise whatever the diagnosis (the posterior's sd scales as √κ where it
is Gaussian), and "held" counts |z_noise| ≤ 1.96.

Usage: scripts/calibration_summary.py NOISE_STUDY.json [LABEL=NOISE_STUDY.json …]
One line per run and one summary line per file, on stdout. Python 3 standard library only.
"""

import json
import math
import statistics
import sys


def noise_scale(cal):
    """√(κ_noise/κ_stated) for a calibration that measured κ_noise, else None; κ_stated is the
    κ map.json's intervals are stated at (`calibration.intervals.kappa`), else the chains'."""
    noise = cal.get("noise_correlation") or {}
    stated = (cal.get("intervals") or {}).get("kappa") or cal.get("kappa")
    if not noise.get("kappa") or not stated:
        return None
    return math.sqrt(noise["kappa"] / stated)


def run_line(run):
    z = [(p["map"] - p["truth"]) / p["sd"] for p in run["parameters"].values() if p.get("sd")]
    cal = run.get("calibration") or {}
    scale = noise_scale(cal)
    extra = ""
    if scale:
        zn = [x / scale for x in z]
        extra = (f"  κ_noise {cal['noise_correlation']['kappa']:.1f}: median|z| "
                 f"{statistics.median(abs(x) for x in zn):5.2f} held {sum(abs(x) <= 1.96 for x in zn)}/{len(zn)}")
    verdict = (run.get("diagnosis") or {}).get("verdict")
    median_z = statistics.median(abs(x) for x in z) if z else float("nan")
    return z, (f"  {run['asset']:<14} σ{run['sigma']:<4g} median|z| {median_z:5.2f}  covered "
               f"{run['covered']}/{run['total']}  median error {100 * (run['median_rel_error'] or 0):.3f} %  "
               f"κ {cal.get('kappa', float('nan')):.1f}  max R̂ {run.get('max_rhat') or float('nan'):.3f}  {verdict}{extra}")


def summarise(label, path):
    study = json.load(open(path))
    zs, zns, covered, total, errors = [], [], 0, 0, []
    print(f"{label}: {path}")
    for run in study["runs"]:
        if not run.get("parameters"):
            print(f"  {run['asset']} σ{run['sigma']:g}: no result ({'; '.join(run.get('notes', []))})")
            continue
        z, line = run_line(run)
        print(line)
        zs += z
        scale = noise_scale(run.get("calibration") or {})
        if scale:
            zns += [x / scale for x in z]
        covered += run["covered"]
        total += run["total"]
        errors.append(run["median_rel_error"])
    if zs:
        print(f"{label}: {len(zs)} parameters, median |z| {statistics.median(abs(x) for x in zs):.3f}, "
              f"RMS z {math.sqrt(sum(x * x for x in zs) / len(zs)):.3f}, covered {covered}/{total} "
              f"({100 * covered / total:.0f} %), median of median errors {100 * statistics.median(errors):.3f} %")
    if zns:
        print(f"{label}: at κ_noise, {len(zns)} parameters, median |z| {statistics.median(abs(x) for x in zns):.3f}, "
              f"RMS z {math.sqrt(sum(x * x for x in zns) / len(zns)):.3f}, "
              f"held {sum(abs(x) <= 1.96 for x in zns)}/{len(zns)}")


def main(argv):
    if not argv:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    for arg in argv:
        label, _, path = arg.rpartition("=")
        summarise(label or path, path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
