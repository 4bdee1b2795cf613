#!/usr/bin/env bash
# One call on a lent GPU: the edge term (likelihood.edges) off and on, side by side. The noise
# study (σ 8, 16, 32) and the clutter assets at their scenes' settings, the backdrop assets
# (house_cloth, and the same house under a plain sky) at default settings over several noise
# seeds with the term on, and Merton's photographs with it on. Every stream at once: one run
# does not fill the GPU. Run from the repository root with the bundle of
# `scripts/device_check.sh prepare` carried; bench/gpu/nvidia-h200/edges.txt holds what it
# printed. The dry run here: OUT=/tmp/e QUICK=--quick NOISE_ASSETS=box CLUTTER_ASSETS= \
#   CLOTH_SEEDS=1 SKY_SEEDS= MERTON_SEEDS= bench/gpu/edges_call.sh
set -uo pipefail
OUT=${OUT:?}
QUICK=${QUICK:-}
export DEVICE_CHECK_NOISE_S=${DEVICE_CHECK_NOISE_S:-500} DEVICE_CHECK_MERTON_S=${DEVICE_CHECK_MERTON_S:-240}
# Twenty runs share the GPU: the backdrop runs' time limit is raised so that sharing does not
# end them (alone, one gets several times the evaluations in the default 240 s).
BACKDROP_LIMIT=${BACKDROP_LIMIT:-420}
both="off:likelihood.edges=false on:likelihood.edges=true"

stream() {  # LABEL ASSETS SIGMAS "VARIANT…" [noise_study options…]
  local label=$1 assets=$2 sigmas=$3 variants=$4; shift 4
  DEVICE_CHECK_STEPS=noise DEVICE_CHECK_NOISE_ASSETS=$assets DEVICE_CHECK_NOISE_SIGMAS=$sigmas \
    DEVICE_CHECK_NOISE_VARIANTS="$variants" DEVICE_CHECK_NOISE_ARGS="$QUICK $*" \
    scripts/device_check.sh run "/tmp/out_$label" >"/tmp/out_$label.log" 2>&1
}
with_label() {  # SUFFIX "LABEL:SETS…": every variant's label with the suffix
  local v out=()
  for v in $2; do out+=("${v%%:*}_$1:${v#*:}"); done
  echo "${out[*]}"
}

mkdir -p "$OUT"
# What this call adds to assets/ goes again when it ends (the dry run's checkout stays clean).
trap 'rm -rf assets/house_sky assets/house_cloth/scene_defaults.json' EXIT
rm -rf /tmp/device_noise /tmp/out_*
# The backdrop assets at default settings: their scenes without likelihood and sampler blocks;
# house_sky is house_cloth photographed under a plain sky (its synth_sky.json).
for name in house_cloth house_sky; do
  [ -d "assets/$name" ] || cp -r assets/house_cloth "assets/$name"
  [ "$name" = house_sky ] && cp assets/house_cloth/synth_sky.json assets/house_sky/synth.json
  python3 -c 'import json, sys
s = json.load(open(sys.argv[1])); s.pop("likelihood", None); s.pop("sampler", None)
json.dump(s, open(sys.argv[2], "w"), indent=2)' "assets/$name/scene.json" "assets/$name/scene_defaults.json"
done

echo "start $(date -u +%T)"
# The first call unpacks the driver's libraries; the others start once it has.
DEVICE_CHECK_STEPS=merton DEVICE_CHECK_MERTON_SEEDS="${MERTON_SEEDS-1 2}" \
  DEVICE_CHECK_MERTON_ARGS="--set likelihood.edges=true" scripts/device_check.sh run "$OUT/merton" \
  >"$OUT/merton.log" 2>&1 &
sleep 15
pids=()
for seed in ${CLOTH_SEEDS-1 2 3 4 5}; do
  stream "cloth$seed" house_cloth 8 "on_cloth_s$seed:likelihood.edges=true" --seed "$seed" --scene scene_defaults.json \
    --set sampler.time_limit="$BACKDROP_LIMIT" &
  pids+=($!)
done
for seed in ${SKY_SEEDS-1 2 3}; do
  stream "sky$seed" house_sky 8 "on_sky_s$seed:likelihood.edges=true" --seed "$seed" --scene scene_defaults.json \
    --set sampler.time_limit="$BACKDROP_LIMIT" &
  pids+=($!)
done
for name in ${NOISE_ASSETS-box house stairs poster}; do
  stream "$name" "$name" "${SIGMAS:-8,16,32}" "$(with_label "$name" "$both")" & pids+=($!)
done
for name in ${CLUTTER_ASSETS-crate_clutter house_annex}; do
  stream "$name" "$name" 16 "$(with_label "$name" "$both")" & pids+=($!)
done
wait "${pids[@]}"
echo "noise done $(date -u +%T)"
for work in /tmp/device_noise/*; do
  [ -f "$work/noise_study.json" ] && python3 scripts/calibration_summary.py "$(basename "$work")=$work/noise_study.json"
done >"$OUT/noise.txt" 2>&1
(cd /tmp/device_noise && find . -name map.json -o -name noise_study.json -o -name log.txt -o -name report.md |
   tar czf "$OUT/noise.tar.gz" -T -)
tar czf "$OUT/logs.tar.gz" /tmp/out_*.log 2>/dev/null
wait
cp "$OUT/merton/run.txt" "$OUT/merton.txt" 2>/dev/null
echo "end $(date -u +%T)"
cat "$OUT/noise.txt" "$OUT/merton.txt" 2>/dev/null
