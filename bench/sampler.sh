#!/usr/bin/env bash
# The sampler row (bench/RESULTS.md, "Sampler"): default runs of bundled assets — the scene
# without its likelihood and sampler blocks, photographs synthesised at σ — with today's
# sampler and with the legacy one (tempered replicas throughout, random walk only), so that
# both come from one binary and one machine. Prints one markdown row per run.
# z = (MAP − truth) / sd per parameter (calibrated: median |z| 0.67, RMS 1).
# SAMPLER_BENCH_KINDS picks and orders the samplers (default "legacy today"); "all_chains" is
# today's with every cooled replica sampling on (sampler.posterior_chains=0).
#
#   bench/sampler.sh [-s SIGMA] [-b BUILD] [-n SEEDS] ASSET…    e.g. bench/sampler.sh house box
set -euo pipefail
cd "$(dirname "$0")/.."
sigma=16 build=build seeds=1
while getopts "s:b:n:" opt; do
  case $opt in
    s) sigma=$OPTARG ;; b) build=$OPTARG ;; n) seeds=$OPTARG ;;
    *) echo "usage: bench/sampler.sh [-s SIGMA] [-b BUILD] [-n SEEDS] ASSET…" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -gt 0 ] || { echo "bench/sampler.sh: name at least one asset (box house stairs poster …)" >&2; exit 2; }
vk=$build/apps/vkrecon
[ -x "$vk" ] || { echo "bench/sampler.sh: $vk not built (scripts/build.sh)" >&2; exit 2; }
work=$(mktemp -d)
# The scene is written beside the asset's, whose textures it names by relative paths.
scene_name=scene_sampler_bench_$$.json
trap 'rm -rf "$work" assets/*/"$scene_name"' EXIT
legacy=(--set sampler.cool_after_settling=false --set sampler.independence_share=0)

echo "| asset | σ | seed | sampler | ended by | iterations | evaluations | wall s | max R̂ | min ESS | ESS per 1,000 evaluations | median error (% of prior) | median \|z\| | RMS z | covered | verdict |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for name in "$@"; do
  for seed in $(seq 1 "$seeds"); do
    images=$work/${name}_$seed scene=assets/$name/$scene_name
    python3 -c 'import json, sys
s = json.load(open(sys.argv[1])); s.pop("likelihood", None); s.pop("sampler", None)
s["sampler"] = {"seed": int(sys.argv[3])}
json.dump(s, open(sys.argv[2], "w"), indent=2)' "assets/$name/scene.json" "$scene" "$seed"
    "$vk" synth "assets/$name/scene.json" --at "assets/$name/truth.json" --noise "$sigma" --seed "$seed" -q -o "$images"
    # Alternating the two samplers, legacy first.
    for kind in ${SAMPLER_BENCH_KINDS:-legacy today}; do
      args=()
      [ "$kind" = legacy ] && args=("${legacy[@]}")
      [ "$kind" = all_chains ] && args=(--set sampler.posterior_chains=0)
      start=$SECONDS
      "$vk" run "$scene" -q "${args[@]}" --set cameras="$images/cameras.json" --set images="$images" \
        -o "$work/run" >/dev/null 2>&1 || true
      python3 - "$work/run/map.json" "assets/$name/truth.json" "assets/$name/scene.json" \
        "$name" "$sigma" "$seed" "$kind" "$((SECONDS - start))" <<'PY'
import json, statistics, sys
m, t, s = (json.load(open(p)) for p in sys.argv[1:4])
name, sigma, seed, kind, wall = sys.argv[4:9]
width = {k: v["prior"]["uniform"][1] - v["prior"]["uniform"][0] for k, v in s["parameters"].items()}
error = statistics.median(abs(v["map"] - t[k]) / width[k] for k, v in m["parameters"].items())
covered = sum(v["q025"] <= t[k] <= v["q975"] for k, v in m["parameters"].items())
# z = (MAP − truth) / sd: a calibrated posterior has median |z| 0.67 and RMS z 1.
z = [(v["map"] - t[k]) / v["sd"] for k, v in m["parameters"].items() if v["sd"] > 0]
median_z = statistics.median(abs(x) for x in z) if z else float("nan")
rms_z = (sum(x * x for x in z) / len(z)) ** 0.5 if z else float("nan")
run = m["sampling"]
per_1000 = 1000.0 * run["min_ess"] / m["evaluations"] if run["min_ess"] else float("nan")
print(f"| {name} | {sigma} | {seed} | {kind} | {run['ended_by']} | {m['iterations']} | {m['evaluations']} | {wall} "
      f"| {run['max_rhat']:.3f} | {run['min_ess']:.0f} | {per_1000:.1f} | {100 * error:.3f} "
      f"| {median_z:.2f} | {rms_z:.2f} | {covered}/{len(m['parameters'])} | {m['diagnosis']['verdict']} |")
PY
      rm -rf "$work/run"
    done
  done
done
