#!/usr/bin/env python3
"""Writes bench/RESULTS.md (to stdout) from one `vkrecon bench --json` result file.

Usage: bench/report.py bench/results-<device>.json > bench/RESULTS.md

Python 3 standard library only. The PNG plots beside RESULTS.md are drawn by
`vkrecon bench --plots bench` (engine/image/LinePlot.h); this script only links them.
Every number quoted is a median over the repeats of one run (see each row's `repeats`).
"""

import glob
import json
import os
import sys

SURFACE_PASSES = ["depth", "view_texture", "interior", "composite", "reduce"]
COMPOSITE_ROWS = 16  # texels each composite.comp invocation sums before the subgroup sum (kRows)
SWEEPS = [
    ("triangles", "Triangles (tessellated cylinder)", "triangles", "log₁₀ triangles"),
    ("backfacing", "Share of back-facing triangles (2 048-triangle grid)", "share", "share back-facing"),
    ("near_clip", "Triangles crossing the near plane (256 ground strips, 512 triangles)", "share", "share of strips crossing"),
    ("cameras", "Number of cameras", "cameras", "cameras"),
    ("atlas", "Atlas size", "atlas side", "log₂ atlas side"),
    ("batch", "Batch size K (the `house` configuration)", "row", "log₂ K"),
]


def num(x, digits=2):
    if x is None:
        return "–"
    if abs(x) >= 1000:
        return f"{x:,.0f}".replace(",", " ")
    return f"{x:.{digits}f}"


def pct(x):
    return "–" if x is None else f"{100 * x:.0f} %"


def mib(b):
    return f"{b / 2**20:.1f} MiB"


def pass_ms(row, name):
    return row.get("passes_ms", {}).get(name)


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def row_cells(r, first):
    if r.get("skipped"):
        return [first, r["batch"], "", "skipped: " + r["skipped"].split(": ")[-1]] + [""] * 10
    return [first, r["batch"], f"{r.get('turns', '?')}/{r['repeats']}", num(r["hypotheses_per_s"]), num(r["wall_ms"]), num(r.get("cpu_ms")),
            *[num(pass_ms(r, p)) for p in SURFACE_PASSES],
            num(r.get("view_textures_per_s"), 0),
            pct(r["share_of_ceiling"].get("view_texture")), pct(r["share_of_ceiling"].get("composite"))]


SURFACE_HEADER = ["row", "K", "turns/evals", "hyp/s", "wall ms/hyp", "CPU ms/hyp", "depth", "view_texture", "interior", "composite",
                  "reduce¹", "view textures/s", "view/fill ceiling", "composite/copy ceiling"]


def where_time_goes(house, ceilings):
    """The `house` row's passes against the ceilings; returns markdown lines."""
    fill, copy = ceilings["fill_fragments_per_s"], ceilings["copy_bytes_per_s"]
    cams, texels = house["cameras"], house["surface_texels"]
    pixels = house["width"] * house["height"]
    atlas = house["atlas"] ** 2
    work = {
        "depth": (cams * pixels, "fragments", fill),
        "view_texture": (cams * texels, "fragments", fill),
        "interior": (texels, "fragments", fill),
        "composite": (atlas * (cams * 8 + 4), "bytes", copy),
    }
    gpu = sum(house["passes_ms"].values())
    rows, bound_ms = [], 0.0
    for p in SURFACE_PASSES:
        ms = pass_ms(house, p)
        if ms is None:
            continue
        if p in work:
            amount, unit, ceiling = work[p]
            at_ceiling = amount / ceiling * 1e3
            bound_ms += at_ceiling
            rate = amount / (ms * 1e-3)
            rows.append([p, num(ms), pct(ms / gpu), f"{amount / 1e6:.2f} M{unit}",
                         f"{rate / 1e6:.0f} M{unit}/s", pct(rate / ceiling), num(at_ceiling, 3)])
        else:
            rows.append([p, num(ms), pct(ms / gpu), "–", "–", "–", "–"])
    lines = [table(["pass", "GPU ms/hyp", "share of GPU time", "work per hypothesis", "rate", "share of ceiling",
                    "ms at the ceiling"], rows)]
    host = house["wall_ms"] - gpu
    lines.append("")
    host_text = (f"the host side (matrices, recording, submit, wait, read-back) adds {num(host)} ms" if host > 0.5 else
                 "the host side (matrices, recording, submit, wait, read-back) is lost in the noise")
    lines.append(f"GPU time {num(gpu)} ms per hypothesis, wall clock {num(house['wall_ms'])} ms: {host_text}. "
                 f"If every pass ran at its ceiling the same work would take {num(bound_ms, 1)} ms, "
                 f"about {num(1e3 / bound_ms, 0)} hypotheses/s: the gap is shading and compute cost, not memory "
                 f"or raster bandwidth.")
    return lines


def sweep_rows(rows, sweep):
    return [r for r in rows if r["sweep"] == sweep and not r.get("skipped")]


def analysis(res, by_name, rows):
    """Why the `house` row is where it is, read off the sweeps of the same run; markdown lines."""
    house = by_name["house"]
    ceilings = res["ceilings"]
    gpu = sum(house["passes_ms"].values())
    out = []
    cams = house["cameras"]
    comp = pass_ms(house, "composite") or 0.0
    view = pass_ms(house, "view_texture") or 0.0
    out.append(f"- **Composite ({num(comp)} ms, {pct(comp / gpu)} of the GPU time).** It reads "
               f"{house['atlas']}² texels × ({cams} views × 8 bytes + 4) = "
               f"{house['atlas'] ** 2 * (cams * 8 + 4) / 1e6:.1f} MB per hypothesis, at "
               f"{pct(house['share_of_ceiling'].get('composite'))} of the compute-copy ceiling.")
    cs = sweep_rows(rows, "cameras")
    if len(cs) >= 2:
        a, b = cs[0], cs[-1]
        out.append(f"  Across the camera sweep it takes {num(pass_ms(a, 'composite'))} ms with {a['cameras']} views and "
                   f"{num(pass_ms(b, 'composite'))} ms with {b['cameras']}, though it reads "
                   f"{(b['cameras'] * 8 + 4) / (a['cameras'] * 8 + 4):.0f}× more: its cost is per texel, not per byte. "
                   "What is per texel in composite.comp: per-lane `imageLoad`s of storage images (the mask and each "
                   "view), the decoding of each view (colour correction, noise variance), the robust consensus "
                   "(docs/internals/LIKELIHOOD.md: a loss that saturates, and up to 3 reweighting rounds where a view "
                   "disagrees) and the loss. A workgroup is one subgroup; each invocation sums a column of "
                   f"{COMPOSITE_ROWS} texels and the subgroup adds its lanes (`subgroupAdd`), with no shared memory and "
                   "no `barrier()`: llvmpipe runs a shader with barriers as coroutines, and the earlier fixed-order "
                   "shared-memory tree per 16×16 texels made the house composite 22.6 ms (16×128 texels: 9.1 ms; "
                   "none: 6.1 ms, same machine, alternating). The view count is a specialisation constant, so the "
                   "loop over views unrolls (6.0 → 4.6 ms).")
    out.append("  The robust statistic (docs/internals/LIKELIHOOD.md, \"The statistic\") made it about 2.5× dearer than the plain mean and deviation. "
               "Measured by alternating builds (`vkrecon bench --only house`, 4 turns each, medians, 2026-11-24): "
               "the robust composite at first 12.4 ms; decoding the halves by their bits instead of "
               "`unpackHalf2x16` 9.7 ms; selecting unseen views (weight 0) instead of skipping them with "
               "`continue` 7.8 ms (same values to the bit). Of that, the image loads alone take 4.1 ms and "
               "the loads with decoding 5.0 ms (variants that compute nothing else); the consensus and the loss "
               "the rest. Kept the views in registers for the reweighting rather than re-reading them; "
               "`[[unroll]]` and caching e² per round changed nothing measurable.")
    out.append("  Two passes over each column (2026-11-27). llvmpipe runs both sides of an `if` under a lane mask "
               "for every SIMD group, and leaves a loop only once no lane goes on (at least one pass through its "
               "body), so the three reweighting rounds under `if (a view is beyond the flat top)` were paid by "
               "every texel. Now a first pass scores every texel with the plain χ² (exact where every view lies "
               "within the flat top, and no exp) and marks the others; a loop of its own redoes only those "
               "robustly, as often as the SIMD group's lanes need it. The texels' sums are kept in registers by "
               "selects and added in row order, so the results are bit-identical (Merton's likelihood sweeps at "
               "levels 0 and 1 and its `--dump` byte-equal). `vkrecon bench --only house`, three binaries "
               "alternating, 4 turns each, medians: composite 3.94 ms (one pass, rounds under the `if`) → 3.22 "
               "(the rounds a loop of a per-texel count) → 2.68 (two passes); the row 58.83 → 61.71 → 64.67 "
               "hypotheses/s, 32.18 → 30.09 → 28.80 CPU ms. Taken apart (timing-only variants, 3 turns): the "
               "first pass alone 2.2 ms, the robust loop's one obligatory pass ~0.3 ms, its useful work ~0.2 ms. "
               "A `float[16]` for the row sums, indexed at run time, went to per-lane scratch memory and cost "
               "more than the second pass saved (3.1–3.7 ms), and unrolling the rows (constant indices) 4.2 ms. "
               "For the same reason the dump images' three `imageStore`s, behind a push constant that is 0 in "
               "every evaluation, cost their lane loops under the mask: behind a specialisation constant instead "
               "(a second pipeline, used only for `--dump` and a run's outputs) the composite went 2.62 → 2.04 ms "
               "and the row 65.09 → 68.06 hypotheses/s (3 alternations, medians; bit-identical, dumps included). "
               "And the first pass now loops over a column's exterior surface rows only (the mask read first), so "
               "rows off the charts or interior are skipped where no lane needs them: about 2.1 → 2.0 ms. The "
               "session's first binary against the last, alternating, 4 turns each: composite 4.02 → 1.92 ms, "
               "interior 0.88 → 0.57 ms, the row 55.65 → 64.50 hypotheses/s and 33.96 → 28.93 CPU ms (a busy "
               "hour; medians).")
    red = ceilings.get("reduction_texels_per_s")
    if red:
        red_ms = house['atlas'] ** 2 / red * 1e3
        out.append(f"  Timed alone (the reduction probe above), the reduction of a {house['atlas']}² atlas takes "
                   f"{red_ms:.2f} ms, {pct(red_ms / comp)} of the composite here: the rest is the image loads and "
                   "the arithmetic.")
    ats = sweep_rows(rows, "atlas")
    if len(ats) >= 2:
        a, b = ats[0], ats[-1]
        out.append(f"  Over the atlas sweep it grows from {num(pass_ms(a, 'composite'))} ms at {a['atlas']}² to "
                   f"{num(pass_ms(b, 'composite'))} ms at {b['atlas']}² ({(b['atlas'] / a['atlas']) ** 2:.0f}× the "
                   "texels): linear in texels.")
    if view:
        per_cam = view / cams
        out.append(f"- **View-specific texture pass ({num(view)} ms, {pct(view / gpu)}; {num(per_cam)} ms per camera).** "
                   f"It shades {house['surface_texels'] / 1e3:.0f} k surface texels per camera at "
                   f"{pct(house['share_of_ceiling'].get('view_texture'))} of the fill ceiling. The projection is already "
                   "per vertex (view_texture.vert); what is left per texel is the fragment shader's normalisation, "
                   "angle weight, slope-scaled depth test, the depth-map lookup and a trilinear `textureLod` at a "
                   "computed LOD. Taking pieces out one at a time (likelihood --profile, house): the trilinear "
                   "sample is about 45 % of the pass, the depth-map lookup 14 %, rasterising and writing the "
                   "layer 18 % (before the per-hypothesis clear of the layers was dropped), the arithmetic the "
                   "rest. Sampling a coarser mip is faster (LOD + 1: −8 %), so "
                   "the LOD rule is also a cost: the implicit LOD of `texture()` (the footprint's longer side) "
                   "was 17 % faster but blurs oblique views more than frontal ones, and the views then disagree "
                   "at the truth (the CPU-reference tests fail); kept the per-texel area rule.")
    ts = sweep_rows(rows, "triangles")
    if len(ts) >= 2:
        a, b = ts[0], ts[-1]
        extra = (pass_ms(b, "depth") - pass_ms(a, "depth")) / b["cameras"] / max(b["triangles"] - a["triangles"], 1)
        out.append(f"- **Triangles.** From {a['triangles']} to {b['triangles']} triangles the depth pass goes from "
                   f"{num(pass_ms(a, 'depth'))} to {num(pass_ms(b, 'depth'))} ms and the view pass from "
                   f"{num(pass_ms(a, 'view_texture'))} to {num(pass_ms(b, 'view_texture'))} ms per hypothesis: about "
                   f"{extra * 1e6:.0f} ns of depth pass per triangle and camera. The assets have tens to hundreds of "
                   "triangles, where the per-texel passes dwarf the per-triangle cost.")
    bs = sweep_rows(rows, "backfacing")
    if len(bs) >= 2:
        a, b = bs[0], bs[-1]
        va, vb = pass_ms(a, "view_texture"), pass_ms(b, "view_texture")
        flat = abs(vb - va) < 0.1 * va
        out.append(f"- **Back-facing triangles**: view pass {num(va)} ms with none, {num(vb)} ms with all; CPU "
                   f"{num(a.get('cpu_ms'))} → {num(b.get('cpu_ms'))} ms per hypothesis. "
                   + ("The fragment shader returns early for a back-facing texel, yet that saves nothing measurable, "
                      "most likely because llvmpipe runs a shader over blocks of fragments and executes divergent "
                      "branches under a mask: an early `return` (writing weight 0) then costs about as much as the "
                      "full shader. "
                      if flat else "The fragment shader's early return for back-facing texels shows in the view pass. ")
                   + "The depth pass draws them either way.")
    ns = sweep_rows(rows, "near_clip")
    if len(ns) >= 2:
        a, b = ns[0], ns[-1]
        out.append(f"- **Near-plane crossings** (every strip the same atlas area): depth pass "
                   f"{num(pass_ms(a, 'depth'))} → {num(pass_ms(b, 'depth'))} ms, view pass "
                   f"{num(pass_ms(a, 'view_texture'))} → {num(pass_ms(b, 'view_texture'))} ms from none to "
                   f"{b['clipped_triangles']} crossing triangles per camera (CPU {num(a.get('cpu_ms'))} → "
                   f"{num(b.get('cpu_ms'))} ms per hypothesis). Crossing triangles are clipped by the rasteriser in "
                   "the depth pass and cover more of the image there; in the view pass their texels behind the "
                   "camera end early (§5.5.1).")
    ks = sweep_rows(rows, "batch")
    if len(ks) >= 2:
        a, b = ks[0], ks[-1]
        rise = b["cpu_ms"] / a["cpu_ms"] - 1
        text = (f"- **Batching** gains nothing on lavapipe, as LAVAPIPE.md predicts (a submission costs tens of µs "
                f"against tens of ms per hypothesis). CPU ms per hypothesis over K = "
                + ", ".join(f"{r['batch']}: {num(r.get('cpu_ms'))}" for r in ks) + ". ")
        if rise > 0.05:
            text += (f"Per hypothesis it even costs {pct(rise)} more at K = {b['batch']} than at K = {a['batch']}; "
                     "every K evaluates the same 16 proposals in turn, so the hypotheses are not the cause. "
                     "Where the extra goes is in the pass columns above.")
        out.append(text)
    lv = [by_name[n] for n in ("house/level1", "house/level2") if n in by_name and not by_name[n].get("skipped")]
    if lv:
        out.append("- **Coarse levels** (§7.3) cut every pass: `house` at level 0 "
                   + num(house["hypotheses_per_s"]) + " hypotheses/s, "
                   + ", ".join(f"level {r['level']} {num(r['hypotheses_per_s'])}" for r in lv)
                   + " (CPU ms " + ", ".join(num(r.get("cpu_ms")) for r in [house] + lv) + ").")
    out.append("")
    target = res.get("bars", {}).get("house_hypotheses_per_s", {}).get("bar", 60.0)
    bound = 1e3 / target
    met = house["hypotheses_per_s"] >= target
    out.append(f"For {num(target, 0)} hypotheses/s a `house` hypothesis may take at most {bound:.1f} ms of wall clock; it takes "
               f"{num(house.get('wall_ms'))} ms here ({'met' if met else 'not met'}), of which the GPU time is "
               f"{num(gpu)} ms, {pct(view / gpu) if view else '?'} of it in the view pass and "
               f"{pct(comp / gpu) if comp else '?'} in the composite. Neither is near a ceiling of the device, so "
               "the remedies are in the shaders (see below), not in the hardware. The same binary reads up to "
               "±25 % apart on this shared machine from one minute to the next (LAVAPIPE.md), and from one day "
               "to the next by more (the noise study's `box` run at σ 16, the same binary making the same "
               "chains: 292 CPU s on 2026-11-24, 419 on 2026-11-25, 205 on 2026-11-27, on an otherwise idle "
               "machine; this table's `house` row read 40.90 hypotheses/s and 45.31 CPU ms per hypothesis on "
               "2026-11-24 and 58.65 and 32.36 on 2026-11-27, when the noise study's runs, the same chains to the "
               "digit, took half the CPU seconds of 2026-11-25: mostly the host, not the code), so the margin "
               "matters as much as the median, and a bar met on one day's host need not be met on the next. "
               "After the composite and interior changes of 2026-11-27 this table read 67.15 hypotheses/s (04:47); "
               "three `vkrecon bench --only house` runs straight after it read 66.17, 71.04 and 69.76 (median "
               "69.76; CPU ms 28.25, 26.42, 26.73; the composite 13 % of the GPU time in each), and three "
               "`--only batch` sweeps K16/K1 1.012, 1.026 and 1.026 (an hour earlier, with the same shaders but for "
               "the last composite change: 62.37, 66.64, 57.33 and 1.000, 1.025, 0.969). Batching's bar stays a "
               "coin toss on this device, where a submission costs nothing next to a hypothesis.")
    out.append("")
    out.append("What was done and what would speed it further:")
    out.append("")
    out.append("1. Composite (done: subgroup sums, no barriers; the view count a specialisation constant, so the "
               "loop unrolls: 6.0 → 4.6 ms; 2026-11-27, the robust rounds only for the texels that need them, in "
               "a second pass, and the dump stores compiled out: 3.94 → 2.04 ms, above). Of what is left, the "
               "robust loop's obligatory pass took ~0.3 ms when measured (two tiles per invocation would halve "
               "it), its work ~0.2 ms, the rest is the first pass: the image loads and the plain statistic. Reading the views from a storage buffer of packed halves instead of "
               "storage images was slower (8.4 against 6.1 ms, composite side alone), and so was `texelFetch` of "
               "the views and the mask as sampled images (9.0–10.4 against 6.1–7.0 ms, three alternations, "
               "2026-11-24). At the copy ceiling the "
               "composite's bytes would take "
               f"{house['atlas'] ** 2 * (cams * 8 + 4) / ceilings['copy_bytes_per_s'] * 1e3:.1f} ms.")
    out.append("2. View pass (done: the layers are no longer cleared per hypothesis, since every chart texel is "
               "written and the composite reads no other: 22.7 → 19.0 ms). Done: host-side culling "
               "(pipelines/passes/ViewCulling.h): per hypothesis and camera, faces wholly outside the frustum, "
               "before the near plane, or flat and facing away are drawn by a pipeline that only writes weight 0, "
               "bit-identical to the full shader's result; on `house` that is 18–23 % of the chart area per "
               "camera. Tried and dropped: drawing the ground as a grid of cells so that culling could skip the "
               "cells out of view: lavapipe shades a 4×4 block on a triangle edge once for each triangle, so the "
               "grid's inner edges cost more than the culled cells saved (CPU ms per hypothesis, LP_NUM_THREADS=1, "
               "alternating builds on a busy machine: 49.7/50.1 before, 49.0/48.7 with the grid, 47.2/44.4 "
               "without). Done (2026-11-27): a face of at least 2 % of the charts partly in view (the ground) is "
               "drawn with the full shader only inside the atlas rectangle that holds what the frustum may see, by "
               "scissor, and with weight 0 around it, bit-identical; on `house` the rectangle leaves out 10–18 % "
               "of the ground's chart per camera (27 % of its texels lie outside each view: the rest is a "
               "trapezoid's corners inside the rectangle). View pass 20.3 → 19.2 ms with LP_NUM_THREADS=1 "
               "(medians of 4 alternations); with 2 threads the difference is inside the host's noise. Bands of "
               "rows, each shaded over its own columns (up to 24 scissored draws per camera), left out more but "
               "were not faster. Also tried and dropped: `texelFetch` for the depth map and `noperspective` "
               "varyings (no measurable change, 2026-11-27); earlier, testing the interior mask first and "
               "rejecting interior texels by early depth test, `discard` for `return`, nearest-mip sampling. A "
               "nearest texel instead of the trilinear colour sample (wrong values, timing only) took the view "
               "pass from 10.9 to 8.9 ms: the most the sample costs, not to be had without changing the "
               "likelihood's prefiltering. Where a camera has a mask (a user's, the clutter a run finds, a lens "
               "border) the pass reads the validity mips too, a second trilinear sample per texel: "
               "crate_clutter at its run's MAP with a mask on every camera, `vkrecon likelihood --profile`, view "
               "pass 6.2 → 8.3 ms (2026-11-27). Faces whose projection lies far from every masked pixel would "
               "read 1.0 there, so a host-side test against an integral image of the masked pixels (dilated by the "
               "sample's footprint) could draw them with the pipeline that skips it, bit-identically: not done.")
    out.append("3. Interior pass (done: the positions in the candidate primitives' frames are interpolated from "
               "the vertices instead of a matrix per texel: 3.8 → 1.2 ms; 2026-11-27, a second pipeline without the "
               "fragment stage's search over every node, for hypotheses where no node has more than four candidate "
               "volumes: lavapipe ran that loop's first pass under the mask for every texel, 0.82 → 0.54 ms, 3 "
               "alternations, bit-identical).")
    out.append(f"4. Composite over the charts only (done): it visits only the workgroup tiles that touch a "
               f"chart instead of all {house['atlas']}² = {house['atlas'] ** 2 / 1e3:.0f} k atlas texels "
               f"({house['surface_texels'] / 1e3:.0f} k lie on the surface); about a fifth less composite time "
               "with LP_NUM_THREADS=1 (13.8 → 10.6 and 16.5 → 13.9 ms, alternating).")
    out.append("5. Tried and dropped (2026-11-24): the view pass and the composite as one pass. A fragment "
               "shader rasterised each face once in atlas space, sampled the texel in all six cameras, scored "
               "it over its views in registers (the composite's statistic, the same code), and wrote its "
               "scalars to one texel for a summing compute pass; its evaluations matched the two passes' to "
               "the bit. It was slower: by the wall clock 35.5–36.5 hypotheses/s against 36.0–46.8, pass "
               "times 23.4–24.2 + 0.7 ms against 13.2–17.1 + 5.0–5.4 ms (`vkrecon bench --only house`, three "
               "alternations with the unchanged binary). Taken apart: projecting per texel instead of per "
               "vertex (the fused pass cannot interpolate six cameras' clip positions) costs the view pass "
               "+3 ms (16.5–17.2 against 13.1–14.3 ms); sampling six cameras in one fragment, with the "
               "statistic replaced by a plain sum, 19.6–20.3 ms, more than six passes of one camera; and the "
               "statistic inside the fragment ~3.5 ms where the composite's arithmetic takes ~1 ms. A compute "
               "pass over precomputed texel positions would share the per-texel projection and the "
               "six-camera sampling, so it is not expected to do better here. What is left for 60 "
               "hypotheses/s on this machine is less work per hypothesis, not the same work rearranged: fewer "
               "texels where a texel is smaller than a pixel (an atlas sized by the photographs' footprint), "
               "or coarser levels (6).")
    out.append("6. Run the coarse levels early (§7.3): a level quarters both the texels and the pixels.")
    return out


def main():
    path = sys.argv[1]
    with open(path) as f:
        res = json.load(f)
    rows = res["rows"]
    by_name = {r["name"]: r for r in rows}
    run = res.get("run", {})
    ceilings = res["ceilings"]
    out = []
    w = out.append

    w("# vkrecon bench — results")
    w("")
    w(f"Device: **{res['device']}** ({res.get('device_type', '?')})"
      + (f", on {run.get('cpu', '?')} with {run.get('cores', '?')} cores" if run else "") + ".  ")
    if run:
        w(f"Run: {run.get('date', '?')}, `bench/run.sh` → `{run.get('command', '')}`, "
          f"{num(res.get('seconds', 0), 0)} s; load average before/after: {run.get('load_before', '?')} / "
          f"{run.get('load_after', '?')}.  ")
    w(f"Numbers: `{os.path.basename(path)}` (every row, every pass, memory, soak). How a row is timed: its "
      "likelihood is built and warmed up (the first submission compiles the pipelines), then the rows of one sweep "
      "take turns, round after round, so that load from other programs falls on all of them alike; in a turn a row "
      "calls `Evaluate()` on batches of K hypotheses (one GPU submission each) for at least half a second. Every "
      "figure is the median over the turns of its row within this one run (`turns/evals`: turns and `Evaluate()` "
      "calls). Per hypothesis: wall clock (host work and read-back included; hypotheses/s is its inverse), the "
      "process's CPU time, and GPU timestamps around each pass.")
    if res.get("quick"):
        w("")
        w("**This is a `--quick` run: small images and atlases. Its numbers are not the bars' configurations.**")
    load = run.get("load_before", "0").split()
    if load and float(load[0]) > 1.5 * (run.get("cores") or 2):
        w("")
        w(f"**Caveat:** other work was running on this machine during the run (load average {run.get('load_before')}"
          f" → {run.get('load_after')} on {run.get('cores')} cores). lavapipe runs on the same CPU cores, so absolute "
          "rates here are lower than on an idle machine; the ceilings were measured in the same run under the same "
          "load, so the shares of ceiling are the steadier figures.")
    w("")

    # Bars.
    bars = res.get("bars", {})
    w("## Bars")
    w("")
    cores = run.get("cores") or 2
    bar_rows = []
    h = bars.get("house_hypotheses_per_s")
    if h:
        house = by_name["house"]
        cpu = house.get("cpu_ms") or 0
        bracket = f"{num(1e3 / cpu, 1)}–{num(cores * 1e3 / cpu, 1)}" if cpu else "–"
        bar_rows.append([f"`house`, surface likelihood, {house['width']}×{house['height']}, {house['cameras']} cameras, "
                         f"{house['atlas']}² atlas, K = {house['batch']}", f"≥ {num(h['bar'], 0)} hypotheses/s", num(h["value"]),
                         bracket, "**met**" if h["met"] else "**not met**"])
    b = bars.get("batch16_over_batch1")
    if b:
        k1, k16 = by_name.get("batch/1", {}), by_name.get("batch/16", {})
        cpu_ratio = k1["cpu_ms"] / k16["cpu_ms"] if k1.get("cpu_ms") and k16.get("cpu_ms") else None
        bar_rows.append(["batching on this device: hypotheses/s at K = 16 over K = 1 (`house`)",
                         f"≥ {num(b['bar'], 2)}", num(b["value"], 3), num(cpu_ratio, 3),
                         "**met**" if b["met"] else "**not met**"])
    house = by_name.get("house")
    if house and pass_ms(house, "composite"):
        share = pass_ms(house, "composite") / sum(house["passes_ms"].values())
        bar_rows.append(["robust composite (the likelihood for photographs): its share of the `house` row's GPU time", "≤ 15 %",
                         pct(share), "–", "**met**" if share <= 0.15 else "**not met**"])
    w(table(["bar", "target", "measured (wall clock)", "from CPU time²", "status"], bar_rows)
      if bar_rows else "(not evaluated in this run)")
    w("")
    w(f"² From the process's CPU time per hypothesis (all threads, lavapipe's included): on an idle {cores}-core "
      f"machine a hypothesis would take between CPU time / {cores} (perfectly parallel) and CPU time (serial), which "
      "brackets the idle rate; for batching, CPU time per hypothesis at K = 1 over K = 16. CPU time moves less "
      "with other programs' load than wall time, but it moves too (shared caches and cores). The status follows "
      "the wall-clock measurement.")
    same = [r for r in rows if not r.get("skipped") and r["kind"] == "surface" and r["sweep"] in ("batch", "assets")
            and r["name"].split("/")[0] in ("house", "batch") and r.get("level", 0) == 0]
    if h and len(same) > 1:
        best = max(same, key=lambda r: r["hypotheses_per_s"])
        least_cpu = min(same, key=lambda r: r["cpu_ms"])
        w("")
        w(f"The `house` configuration was timed {len(same)} times in this run (the `house` row and the batch sweep): "
          f"{num(min(r['hypotheses_per_s'] for r in same))} to {num(best['hypotheses_per_s'])} hypotheses/s by the "
          f"wall clock (best: `{best['name']}`), and the least CPU time per hypothesis, {num(least_cpu['cpu_ms'])} ms "
          f"(`{least_cpu['name']}`), bounds an idle {cores}-core machine at {num(cores * 1e3 / least_cpu['cpu_ms'], 1)} "
          "hypotheses/s. " + ("Even that bound is below the bar." if cores * 1e3 / least_cpu["cpu_ms"] < h["bar"]
                                else "Some readings reach the bar." if best["hypotheses_per_s"] >= h["bar"]
                                else "The bound reaches the bar; no reading does."))
    w("")

    # Ceilings.
    w("## The device's own ceilings")
    w("")
    w(table(["ceiling", "measured", "how"], [
        ["compute copy", f"{ceilings['copy_bytes_per_s'] / 1e9:.2f} GB/s (read + write)",
         f"a compute shader copying a {mib(ceilings['copy_buffer_bytes'])} storage buffer, uvec4 per invocation"],
        ["fill", f"{ceilings['fill_fragments_per_s'] / 1e6:.0f} Mfragments/s",
         f"constant colour into a {ceilings['fill_side']}² RGBA16F target, {ceilings['fill_draws']} full-target "
         "draws, each its own rendering behind a barrier (llvmpipe drops covered opaque draws)"],
    ] + ([["probe: the composite's reduction alone",
           f"{ceilings['reduction_texels_per_s'] / 1e6:.1f} Mtexels/s",
           f"columns of {COMPOSITE_ROWS} texels per invocation, then a subgroup sum, over "
           f"{ceilings['fill_side']}² made-up texels, no image "
           "reads (not a device ceiling: a piece of the composite pass, timed alone)"]]
         if ceilings.get("reduction_texels_per_s") else [])))
    w("")
    w("Each ceiling is the better of two measurements, at the start of the run and after the rows. "
      "Each pass of the surface likelihood is reported as a share of the ceiling that bounds it: the depth pass "
      "as cameras × image pixels, the view-specific texture pass as cameras × surface texels, the interior pass as "
      "surface texels (all fragments, against the fill ceiling) and the composite as the bytes it must read, atlas² × "
      "(8 bytes × cameras + 4), against the copy ceiling.")
    w("")

    # Where the time goes.
    if "house" in by_name and not by_name["house"].get("skipped"):
        w("## Where the time goes (`house`)")
        w("")
        out.extend(where_time_goes(by_name["house"], ceilings))
        w("")
        out.extend(analysis(res, by_name, rows))
        w("")

    # Assets.
    assets = [r for r in rows if r["sweep"] == "assets"]
    if assets:
        w("## The four assets")
        w("")
        w("Reference images synthesised at each asset's truth (640×480 unless `--quick`), a 512² atlas, "
          "K = 16 hypotheses near the truth per submission; `house` with its first 6 cameras.")
        w("")
        surf = [r for r in assets if r["kind"] == "surface"]
        if surf:
            w(table(SURFACE_HEADER, [row_cells(r, f"`{r['name']}` ({r['cameras']} cameras)") for r in surf]))
            w("")
        img = [r for r in assets if r["kind"] != "surface"]
        if img:
            names = sorted({p for r in img for p in r.get("passes_ms", {})},
                           key=lambda p: ["depth", "warp", "compare", "reduce"].index(p)
                           if p in ["depth", "warp", "compare", "reduce"] else 99)
            w("Image-space likelihood (GPU ms per hypothesis by pass):")
            w("")
            w(table(["row", "K", "turns/evals", "hyp/s", "wall ms/hyp", "CPU ms/hyp", *names],
                    [[f"`{r['name']}`", r["batch"], f"{r.get('turns', '?')}/{r['repeats']}",
                      "skipped" if r.get("skipped") else num(r["hypotheses_per_s"]),
                      num(r.get("wall_ms")), num(r.get("cpu_ms")), *[num(pass_ms(r, p)) for p in names]]
                     for r in img]))
            w("")

    # Sweeps.
    w("## Sweeps")
    w("")
    w("Synthetic scenes built in code; the base configuration is 640×480 images, 6 cameras on a ring, a 512² atlas, "
      "a 1 008-triangle cylinder and K = 4 (batching changes nothing on lavapipe; K has its own sweep). One factor "
      "varies per sweep. Plots: hypotheses/s (left) and view-specific textures/s of the view-texture pass alone "
      "(right) against the swept value.")
    w("")
    for sweep, title, xname, xaxis in SWEEPS:
        srows = [r for r in rows if r["sweep"] == sweep]
        if not srows:
            continue
        w(f"### {title}")
        w("")
        def first(r):
            if sweep == "triangles":
                return f"{r['triangles']}"
            if sweep == "backfacing":
                return f"{r['x']:g} ({r['backfacing_triangles']} tri)"
            if sweep == "near_clip":
                return f"{r['x']:g} ({r['clipped_triangles']} tri per camera)"
            if sweep == "atlas":
                return f"{r['atlas']}²"
            if sweep == "batch":
                return f"`{r['name']}`"
            return f"{r['x']:g}"
        w(table([xname] + SURFACE_HEADER[1:], [row_cells(r, first(r)) for r in srows]))
        w("")
        for kind in ("hyps", "view"):
            png = f"{sweep}_{kind}.png"
            if os.path.exists(os.path.join(os.path.dirname(path) or ".", png)):
                label = "hypotheses/s" if kind == "hyps" else "view textures/s"
                w(f"![{label} against {xaxis}]({png})")
        w("")
        w(f"x: {xaxis}; y: hypotheses/s, then view-specific textures/s.")
        w("")

    # Memory.
    w("## Memory")
    w("")
    mem = res.get("memory", {})
    built = [r for r in rows if not r.get("skipped")]
    largest = max(built, key=lambda r: r["device_bytes"]) if built else None
    w(f"Peak host RSS (VmHWM) over the whole run: {mib(mem.get('peak_rss_bytes', 0))} (the rows of a sweep keep "
      "their likelihoods, images and pyramids alive together while they take turns). Device memory "
      f"(`Device::allocated_bytes()`): at most {mib(mem.get('peak_device_bytes', 0))} at once"
      + (f"; the largest single likelihood is `{largest['name']}` with {mib(largest['device_bytes'])}" if largest else "")
      + (f", `house` takes {mib(by_name['house']['device_bytes'])}" if "house" in by_name else "")
      + ". Each row's own figure is its `device_bytes` (the ceilings' 2 × 128 MiB buffers are not counted).")
    w("")
    soak = res.get("soak")
    if soak:
        s = soak["samples"]
        w(f"Soak: {soak['evaluations']} evaluations ({soak['configuration']}), {num(soak['hypotheses_per_s'])} "
          f"hypotheses/s. Memory **{'flat' if soak['flat'] else 'GROWING'}** (flat: last RSS ≤ first × 1.05 + 4 MiB "
          "and device bytes unchanged).")
        w("")
        w(table(["evaluations", "host RSS", "device bytes"],
                [[x["evaluations"], mib(x["rss_bytes"]), mib(x["device_bytes"])] for x in s]))
        w("")

    w("## Notes")
    w("")
    w("¹ `reduce` is one pass for the whole batch; `LastPassTimesMs()` divides it by K like the other passes "
      "(results written before 2026-11-21 18:15 UTC report it per batch).")
    w("")
    w("`cameras/1` is skipped: the surface likelihood compares views and needs at least two cameras.")
    w("")
    w("The depth pass writes depth only, with no fragment shader, so it can exceed the colour-fill ceiling "
      "(a share above 100 %).")
    w("")
    w("GPU timestamps on lavapipe measure CPU work too: when other programs load the machine, pass times grow with "
      "the wall clock. The shares between passes and the CPU ms per hypothesis are the figures that survive a "
      "loaded machine.")
    w("")
    others = sorted(p for p in glob.glob(os.path.join(os.path.dirname(path) or ".", "results-*.json"))
                    if os.path.abspath(p) != os.path.abspath(path))
    if others:
        w("Other devices' results in this folder:")
        w("")
        for p in others:
            with open(p) as f:
                o = json.load(f)
            hh = o.get("bars", {}).get("house_hypotheses_per_s", {}).get("value")
            w(f"- `{os.path.basename(p)}`: {o['device']}, `house` {num(hh)} hypotheses/s")
        w("")
    print("\n".join(out))


if __name__ == "__main__":
    main()
