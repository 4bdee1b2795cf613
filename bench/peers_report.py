#!/usr/bin/env python3
"""The "Peers" section of bench/RESULTS.md from `vkrecon bench --only peers --json`.

Usage: bench/peers_report.py bench/peers.json [--results bench/RESULTS.md] [--plot bench/peers.png]

Splices the section between the markers <!-- peers --> and <!-- /peers --> of RESULTS.md
(appended when they are missing), so that bench/run.sh, which rewrites the throughput
sections from their own JSON, and the peers run, which takes ~45 min, keep each other's
numbers: run.sh calls this script again after it rewrites the file. The analysis text lives
in bench/peers_notes.md (written by hand after looking at the numbers) and is kept as it is.
The plot needs python3-matplotlib (scripts/bootstrap.sh plots); without it the section is
written without the figure.
"""

import argparse
import json
import os
import statistics
import sys

BEGIN, END = "<!-- peers -->", "<!-- /peers -->"


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def fmt(x, digits=0):
    return "—" if x is None else f"{x:.{digits}f}"


def summary(rows, assets, methods):
    """Per (asset, method): the medians the table shows."""
    out = {}
    for a in assets:
        for m in methods:
            rs = [r for r in rows if r["asset"] == a and r["method"] == m]
            if not rs:
                continue
            out[a, m] = {
                "n": len(rs), "reached": sum(r["reached"] for r in rs),
                "evaluations_to": median(r["evaluations_to"] for r in rs),
                "equivalents_to": median(r["equivalents_to"] for r in rs),
                "seconds_to": median(r["seconds_to"] for r in rs),
                "evaluations": median(r["evaluations"] for r in rs),
                "equivalents": median(r["equivalents"] for r in rs),
                "seconds": median(r["seconds"] for r in rs),
                "median_error": median(100 * r["median_error"] for r in rs),
                "max_error": median(100 * r["max_error"] for r in rs),
            }
    return out


def section(data, plot_name, notes):
    assets, methods = data["assets"], data["methods"]
    s = summary(data["rows"], assets, methods)
    # What the bench set for every search (`run` at fewer iterations than the assets' 600).
    sets = data.get("overrides")
    overrides = f"Every search with `--set {' --set '.join(sets)}`. " if sets else ""
    w = []
    w.append("## Peers: finding the MAP, `run` against NLopt")
    w.append("")
    w.append(f"`vkrecon bench --only peers --json` on {data['device']}: per asset, {len(data['seeds'])} noise seeds "
             f"({', '.join(map(str, data['seeds']))}) at σ = {data['sigma']:g} on images at {data['scale']:g}× the "
             f"asset's size, each method from the prior centre on the same likelihood; NLopt's methods "
             f"(`vkrecon fit`, coarse-to-fine) with a budget of {data['budget']:g} full-resolution-equivalent "
             f"evaluations (a level-l evaluation counts 4^-l), `run` with its own schedule, then "
             f"the BOBYQA polish. {overrides}\"To 1 %\": spent when the running MAP first had every parameter within "
             f"{100 * data['tolerance']:g} % of its prior width of the truth (medians over the seeds that got "
             f"there); the error columns: the final MAP's median and largest |MAP − truth| / prior width "
             f"(medians over the seeds). Wall time from the call (photographs loaded, pipelines built) to the "
             f"last evaluation. The whole run took {data['wall_s'] / 60:.0f} min.")
    w.append("")
    w.append("| asset | method | reached 1 % | evaluations to 1 % | full-res eq. to 1 % | s to 1 % | evaluations | "
             "full-res eq. | s | final median error % | final max error % |")
    w.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for a in assets:
        for m in methods:
            c = s.get((a, m))
            if not c:
                continue
            w.append(f"| {a} | {m} | {c['reached']}/{c['n']} | {fmt(c['evaluations_to'])} | {fmt(c['equivalents_to'])} | "
                     f"{fmt(c['seconds_to'], 1)} | {fmt(c['evaluations'])} | {fmt(c['equivalents'])} | {fmt(c['seconds'], 1)} | "
                     f"{fmt(c['median_error'], 3)} | {fmt(c['max_error'], 3)} |")
    w.append("")
    if plot_name:
        w.append(f"![full-resolution equivalents to 1 % and final median error per asset and method]({plot_name})")
        w.append("")
    if notes:
        w.append(notes.strip())
        w.append("")
    w.append("Raw numbers: `bench/peers.json`; the command: `bench/peers.sh` (builds, runs, splices this section).")
    return "\n".join(w)


def plot(data, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("peers_report: no matplotlib (scripts/bootstrap.sh plots): no figure", file=sys.stderr)
        return False
    assets, methods = data["assets"], data["methods"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    width = 0.8 / len(methods)
    for k, m in enumerate(methods):
        xs = [i + (k - (len(methods) - 1) / 2) * width for i in range(len(assets))]
        for ax, key, scale in ((axes[0], "equivalents_to", 1.0), (axes[1], "median_error", 100.0)):
            for x, a in zip(xs, assets):
                vals = [r[key] * scale for r in data["rows"] if r["asset"] == a and r["method"] == m and r[key] is not None]
                ax.scatter([x] * len(vals), vals, s=12, color=f"C{k}", label=m if x == xs[0] else None)
    axes[0].set_ylabel("full-resolution equivalents to 1 % (reached only)")
    axes[1].set_ylabel("final median error, % of prior width")
    for ax in axes:
        ax.set_xticks(range(len(assets)))
        ax.set_xticklabels(assets)
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=len(methods), frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 0.92))
    fig.savefig(path, dpi=90)
    return True


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("json")
    p.add_argument("--results", default=os.path.join("bench", "RESULTS.md"))
    p.add_argument("--plot", default=os.path.join("bench", "peers.png"))
    p.add_argument("--notes", default=os.path.join("bench", "peers_notes.md"))
    args = p.parse_args(argv)
    with open(args.json) as f:
        data = json.load(f)
    drew = plot(data, args.plot)
    notes = open(args.notes).read() if os.path.exists(args.notes) else ""
    text = section(data, os.path.relpath(args.plot, os.path.dirname(args.results) or ".") if drew else None, notes)
    old = open(args.results).read() if os.path.exists(args.results) else ""
    block = f"{BEGIN}\n{text}\n{END}"
    if BEGIN in old and END in old:
        new = old[:old.index(BEGIN)] + block + old[old.index(END) + len(END):]
    else:
        new = old.rstrip("\n") + "\n\n" + block + "\n"
    with open(args.results, "w") as f:
        f.write(new)
    print(f"peers_report: wrote the Peers section of {args.results}", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
