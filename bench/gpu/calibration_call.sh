#!/usr/bin/env bash
# One call on a lent GPU: the noise study under three calibrations, the clutter assets under
# the same, and the sampler's defaults on four assets and Merton (4 seeds), all at once.
# bench/gpu/nvidia-h200/calibration.txt holds what it printed on an H200.
OUT=${OUT:?}
V=${V:-"magnitude:likelihood.sandwich_adjustment=magnitude blocks8:likelihood.sandwich_blocks=8 curvature:likelihood.sandwich_adjustment=curvature"}
noise() {  # SUFFIX ASSETS SIGMAS (no assets: nothing)
  [ -n "$2" ] || return 0
  DEVICE_CHECK_STEPS=noise DEVICE_CHECK_NOISE_ASSETS=$2 DEVICE_CHECK_NOISE_SIGMAS=$3 \
    DEVICE_CHECK_NOISE_VARIANTS="${V//:/_$1:}" scripts/device_check.sh run "/tmp/out_$1" >"/tmp/out_$1.log" 2>&1
}
export DEVICE_CHECK_NOISE_S=${DEVICE_CHECK_NOISE_S:-420} DEVICE_CHECK_NOISE_ARGS=${DEVICE_CHECK_NOISE_ARGS:-}
mkdir -p "$OUT/d"
# The first call unpacks the driver's libraries; the others start once it has.
DEVICE_CHECK_STEPS="defaults merton" DEVICE_CHECK_DEFAULT_RUNS="${DEFAULT_RUNS-box house stairs poster}" \
  DEVICE_CHECK_MERTON_SEEDS="${MERTON_SEEDS-1 2 3 4}" scripts/device_check.sh run "$OUT/d" >"$OUT/d.log" 2>&1 &
sleep 20
pids=()
noise a "${ASSETS_A-box,house}" "${SIGMAS:-8,16,32}" & pids+=($!)
noise b "${ASSETS_B-stairs,poster}" "${SIGMAS:-8,16,32}" & pids+=($!)
noise c "${ASSETS_C-crate_clutter,house_annex}" "${SIGMAS_C:-16}" & pids+=($!)
wait "${pids[@]}"
cat /tmp/out_*/noise.txt >"$OUT/noise.txt" 2>/dev/null
(cd /tmp/device_noise && find . -name map.json -o -name noise_study.json -o -name log.txt -o -name report.md |
   tar czf "$OUT/noise.tar.gz" -T -)
tail -3 /tmp/out_*.log
cat "$OUT/noise.txt"
wait
cat "$OUT/d/run.txt"
