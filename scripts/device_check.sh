#!/usr/bin/env bash
# GPU figures in one step, on a bare GPU machine with no Debian packages and no network.
#
#   scripts/device_check.sh prepare        here: a Release build of vkrecon and the shared
#                                          libraries it needs, in device_bundle/ (≤ 64 MiB),
#                                          with each asset's photographs and lavapipe's
#                                          likelihoods of them (`run` here is the dry run)
#   scripts/device_check.sh run OUT        there (or here for the dry run): `vkrecon devices`,
#                                          the likelihood on every asset against lavapipe's,
#                                          `vkrecon bench --json`, one default `run` of house;
#                                          every result into OUT/ (DEVICE_CHECK_DEFAULT_RUNS="box
#                                          house": runs of those assets with the sampler's and
#                                          likelihood's defaults too; DEVICE_CHECK_MERTON_SEEDS="1 2":
#                                          runs of the Merton example; DEVICE_CHECK_NOISE_VARIANTS=
#                                          "LABEL:K=V,K=V …": the noise study once per variant, side
#                                          by side, over DEVICE_CHECK_NOISE_ASSETS and _SIGMAS, with
#                                          DEVICE_CHECK_NOISE_ARGS; DEVICE_CHECK_STEPS: which steps)
#   bench/device_report.py OUT             back here: the "On a GPU" section of bench/RESULTS.md
#
# The bundle carries its own glibc and loader too: if the machine's libc is older than
# Debian 12's, vkrecon runs under the carried ld.so (DEVICE_CHECK_LOADER=1 forces that).
# Only the GPU's Vulkan driver comes from the machine (its ICD manifest is searched for where
# NVIDIA's container images put it), with glvnd's libraries from the bundle where it lacks them.
# docs/internals/BENCHMARKS.md ("On a GPU") says how the figures are read.
set -euo pipefail
cd "$(dirname "$0")/.."
BUNDLE=device_bundle
AGREE_ASSETS=(box house poster stairs crate_clutter house_annex)

# The likelihood of one asset's photographs at two points: the truth, and the truth moved by a
# twentieth of each prior's width (so the difference between them is compared too).
likelihoods() {  # VKRECON ASSET_DIR IMAGES_DIR
  local vk=$1 asset=$2 images=$3 name
  name=$(basename "$asset")
  for at in truth moved; do
    for kind in surface image; do
      [ "$kind" = image ] && [ "$name" != house ] && continue  # the image-space kind on house alone
      printf '%s %s %s ' "$name" "$at" "$kind"
      # shellcheck disable=SC2086 # $vk is a command line (a loader and its arguments)
      $vk likelihood "$asset/scene.json" --at "$images/$at.json" -q \
        --set cameras="$images/cameras.json" --set images="$images" --set likelihood.kind="$kind" |
        tr '\n' ' '
      echo
    done
  done
}

prepare() {
  export CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1
  cmake -S . -B build-release -G Ninja -DCMAKE_BUILD_TYPE=Release -DVKRECON_UNITY=ON \
    -DVKRECON_MPI=OFF -DBUILD_TESTING=OFF >/dev/null
  cmake --build build-release -j "$(nproc)" --target vkrecon
  rm -rf "$BUNDLE"
  mkdir -p "$BUNDLE/bin" "$BUNDLE/lib/glibc" "$BUNDLE/agree"
  strip -o "$BUNDLE/bin/vkrecon" build-release/apps/vkrecon
  # Every library the binary loads (the Vulkan loader is linked). glibc apart, with the stubs a
  # driver may still name: it is used only with its own loader, never mixed with the machine's.
  ldd build-release/apps/vkrecon | awk '/=>/ {print $3} /ld-linux/ {print $1}' | sort -u |
    while read -r lib; do
      case "$(basename "$lib")" in
        ld-linux*|libc.so*|libm.so*) cp -L "$lib" "$BUNDLE/lib/glibc/" ;;
        *) [ -f "$lib" ] && cp -L "$lib" "$BUNDLE/lib/" ;;
      esac
    done
  for stub in libdl.so.2 libpthread.so.0 librt.so.1; do cp -L "/lib/x86_64-linux-gnu/$stub" "$BUNDLE/lib/glibc/"; done
  # NVIDIA's Vulkan driver lives in libGLX_nvidia, which finds no instance entry point without
  # glvnd's dispatch libraries: a bare GPU machine lacks them (VK_ERROR_INCOMPATIBLE_DRIVER).
  # Debian's packages, unpacked into / there (the device machine's README does the same).
  mkdir -p "$BUNDLE/gl" /tmp/device_check_apt/partial
  local apt_o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/device_check_apt)
  apt-get "${apt_o[@]}" update -qq
  (cd "$BUNDLE/gl" && apt-get "${apt_o[@]}" download -qq libglvnd0 libegl1 libgl1 libglx0 libgles2 libopengl0 2>/dev/null)
  local vk="$BUNDLE/bin/vkrecon"
  for name in "${AGREE_ASSETS[@]}"; do
    local images="$BUNDLE/agree/$name" synth="assets/$name/scene.json"
    # The clutter assets' photographs show what their scene leaves out.
    [ -f "assets/$name/synth.json" ] && synth="assets/$name/synth.json"
    "$vk" synth "$synth" --at "assets/$name/truth.json" --scale 0.5 --noise 8 \
      --seed 1 -q -o "$images"
    cp "assets/$name/truth.json" "$images/truth.json"
    python3 - "assets/$name/scene.json" "$images/truth.json" "$images/moved.json" <<'PY'
import json, sys
scene, truth = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
moved = {}
for name, p in scene["parameters"].items():
    prior = p["prior"]
    if "uniform" in prior:
        lo, hi = prior["uniform"]
        moved[name] = min(hi, truth[name] + (hi - lo) / 20)
    else:  # a normal prior: a tenth of its sd
        moved[name] = truth[name] + prior["normal"][1] / 10
json.dump(moved, open(sys.argv[3], "w"), indent=2)
PY
  done
  # Merton's real photographs, when this checkout has them beside it (step_merton).
  [ -d ../shared/data/merton_college_1 ] && cp -r ../shared/data/merton_college_1 "$BUNDLE/merton"
  echo "device_check: lavapipe's likelihoods (the reference the GPU is compared with)" >&2
  for name in "${AGREE_ASSETS[@]}"; do
    VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \
      likelihoods "$vk" "assets/$name" "$BUNDLE/agree/$name"
  done >"$BUNDLE/agree/lavapipe.txt"
  cat "$BUNDLE/agree/lavapipe.txt" >&2
  du -sh "$BUNDLE" >&2
}

# How to start the carried binary on this machine: directly if its libc is new enough, else
# through the carried loader.
launcher() {
  local lib=$PWD/$BUNDLE/lib bin=$PWD/$BUNDLE/bin/vkrecon
  if [ -z "${DEVICE_CHECK_LOADER:-}" ] && LD_LIBRARY_PATH="$lib:${LD_LIBRARY_PATH:-}" "$bin" --help >/dev/null 2>&1; then
    printf '%s\n' "env LD_LIBRARY_PATH=$lib:${LD_LIBRARY_PATH:-} $bin"
  else
    printf '%s\n' "$lib/glibc/ld-linux-x86-64.so.2 --library-path $lib/glibc:$lib:${LD_LIBRARY_PATH:-} $bin"
  fi
}

# NVIDIA's driver: glvnd's dispatch libraries where the machine lacks them, the driver's own
# libraries and its Vulkan manifest where container images put them.
find_driver() {
  if [ "$(id -u)" -eq 0 ] && command -v nvidia-smi >/dev/null && ! ldconfig -p | grep -q libGLdispatch; then
    for deb in "$BUNDLE"/gl/*.deb; do dpkg -x "$deb" /; done
    ldconfig
  fi
  for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/lib/x86_64-linux-gnu; do
    [ -d "$d" ] && export LD_LIBRARY_PATH="${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}$d"
  done
  if [ -z "${VK_DRIVER_FILES:-}" ]; then
    for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
             /etc/vulkan/icd.d/nvidia_icd.json; do
      [ -f "$f" ] && { export VK_DRIVER_FILES=$f; break; }
    done
  fi
  if [ -z "${VK_DRIVER_FILES:-}" ] && command -v nvidia-smi >/dev/null; then  # elsewhere on a GPU machine
    f=$(find / -xdev -name 'nvidia_icd*.json' 2>/dev/null | head -1 || true)
    [ -n "$f" ] && export VK_DRIVER_FILES=$f
  fi
  # The library the manifest names, wherever the driver was mounted.
  local glx
  glx=$(find /usr/local/nvidia /usr/lib64 /usr/lib/x86_64-linux-gnu -maxdepth 2 -name 'libGLX_nvidia.so.0' 2>/dev/null | head -1 || true)
  [ -n "$glx" ] && export LD_LIBRARY_PATH="$(dirname "$glx"):$LD_LIBRARY_PATH"
  unset VKRECON_VALIDATION  # no validation layer there
}

run() {
  local out=${1:?usage: scripts/device_check.sh run OUT}
  mkdir -p "$out"
  [ -x "$BUNDLE/bin/vkrecon" ] || { echo "device_check: no $BUNDLE/ (run 'prepare' first)" >&2; exit 2; }
  find_driver
  local vk
  vk=$(launcher)
  {
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "launcher: $vk"
    echo "VK_DRIVER_FILES: ${VK_DRIVER_FILES:-}"
    echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2-) ($(nproc) cores)"
    command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
    echo "devices:"
    $vk devices
  } >"$out/machine.txt" 2>&1
  cat "$out/machine.txt"
  # DEVICE_CHECK_STEPS picks the steps (all by default), so a second call can spend its
  # minutes on what the first did not measure.
  for step in ${DEVICE_CHECK_STEPS:-agree bench house defaults merton noise}; do
    echo "== $step"
    local start=$SECONDS
    "step_$step" "$vk" "$out"
    echo "($((SECONDS - start)) s)"
  done
  [ -s "$out/agree.err" ] || rm -f "$out/agree.err"
}

step_agree() {  # VKRECON OUT: the likelihood on every asset against lavapipe's
  local vk=$1 out=$2
  for name in "${AGREE_ASSETS[@]}"; do
    likelihoods "$vk" "assets/$name" "$BUNDLE/agree/$name"
  done >"$out/agree.txt" 2>"$out/agree.err" || true
  paste -d' ' "$BUNDLE/agree/lavapipe.txt" "$out/agree.txt" | head -40
}

step_bench() {  # VKRECON OUT
  local vk=$1 out=$2
  timeout "${DEVICE_CHECK_BENCH_S:-300}" $vk bench --json --assets assets "${DEVICE_CHECK_BENCH_ARGS[@]}" \
    >"$out/bench.json" 2>"$out/bench.err" || echo "bench: exit $?" | tee -a "$out/bench.err"
  tail -3 "$out/bench.err"
}

step_house() {  # VKRECON OUT: house at its scene's settings, full-size photographs at σ 16
  local vk=$1 out=$2 start=$SECONDS images=$2/house_images
  $vk synth assets/house/scene.json --at assets/house/truth.json --noise 16 --seed 1 -q -o "$images"
  # shellcheck disable=SC2086 # DEVICE_CHECK_RUN_ARGS: extra options, for the dry run's time limit
  timeout "${DEVICE_CHECK_RUN_S:-300}" $vk run assets/house/scene.json -q ${DEVICE_CHECK_RUN_ARGS:-} \
    --set cameras="$images/cameras.json" --set images="$images" -o "$out/house_run" \
    >>"$out/run.txt" 2>&1 || echo "run: exit $?" | tee -a "$out/run.txt"
  echo "wall: $((SECONDS - start)) s (synth and run)" >>"$out/run.txt"
  tail -5 "$out/run.txt"
  # Only map.json and the log come back (the device tool returns at most 8 files, 2 folders down).
  cp "$out/house_run/map.json" "$out/run_map.json" 2>/dev/null || true
  rm -rf "$images" "$out/house_run"
}

step_defaults() {  # VKRECON OUT
  local name
  for name in ${DEVICE_CHECK_DEFAULT_RUNS:-}; do default_run "$1" "$name" "$2"; done
}

# Merton's photographs (../shared/data, carried in the bundle when prepare found them) with
# the example's scene, once per seed in DEVICE_CHECK_MERTON_SEEDS: where the chains end, the
# corner, and the log posterior each run's MAP reaches. One line each in OUT/run.txt.
step_merton() {  # VKRECON OUT
  local vk=$1 out=$2 seed data=$BUNDLE/merton
  [ -d "$data" ] || { echo "no $data: skipped"; return; }
  for seed in ${DEVICE_CHECK_MERTON_SEEDS:-}; do
    local start=$SECONDS dir=$out/merton_$seed
    # shellcheck disable=SC2086
    timeout "${DEVICE_CHECK_MERTON_S:-120}" $vk run docs/examples/merton/scene.json -q ${DEVICE_CHECK_MERTON_ARGS:-} \
      --set images="$data/" --set cameras="$data/cameras.json" --set sampler.seed="$seed" -o "$dir" \
      >/dev/null 2>&1 || true
    python3 -c 'import json, sys
m = json.load(open(sys.argv[1])); p = m["parameters"]
print("merton seed", sys.argv[2], json.dumps(m["sampling"]), "log_posterior", m["log_posterior"],
      "evaluations", m["evaluations"], " ".join("%s %.4f [%.4f,%.4f]" % (k, v["map"], v["q025"], v["q975"]) for k, v in p.items()),
      "verdict", m["diagnosis"]["verdict"], "wall_s", sys.argv[3])' "$dir/map.json" "$seed" "$((SECONDS - start))" \
      >>"$out/run.txt" 2>&1 || echo "merton seed $seed: failed" >>"$out/run.txt"
    tail -1 "$out/run.txt"
    rm -rf "$dir"
  done
}

# The noise study (scripts/noise_study.py) once per variant of DEVICE_CHECK_NOISE_VARIANTS
# ("LABEL:K=V,K=V", the --set options of that variant), all at once (one run does not fill the
# GPU). Each variant's noise_study.json and every run's map.json come back in one archive;
# scripts/calibration_summary.py reads them.
step_noise() {  # VKRECON OUT
  local vk=$1 out=$2 spec label work
  local wrapper=$PWD/$BUNDLE/bin/vk
  # Written aside and renamed: streams started together must never exec a half-written one.
  printf '#!/bin/sh\nexec %s "$@"\n' "$vk" >"$wrapper.$$" && chmod +x "$wrapper.$$" && mv -f "$wrapper.$$" "$wrapper"
  for spec in ${DEVICE_CHECK_NOISE_VARIANTS:-}; do
    label=${spec%%:*} work=/tmp/device_noise/$label
    local sets=() kv kvs
    if [ "$spec" != "$label" ]; then
      IFS=, read -r -a kvs <<<"${spec#*:}"
      for kv in "${kvs[@]}"; do sets+=(--set "$kv"); done
    fi
    mkdir -p "$work"
    VKRECON=$wrapper timeout "${DEVICE_CHECK_NOISE_S:-400}" python3 scripts/noise_study.py \
      --assets "${DEVICE_CHECK_NOISE_ASSETS:-box,house,stairs,poster}" --sigmas "${DEVICE_CHECK_NOISE_SIGMAS:-8,16,32}" \
      "${sets[@]}" ${DEVICE_CHECK_NOISE_ARGS:-} --work "$work" --report "$work/report.md" --plot "$work/plot.svg" >"$work/log.txt" 2>&1 &
  done
  wait || true
  (cd /tmp/device_noise && find . -name map.json -o -name noise_study.json -o -name log.txt -o -name report.md |
     tar czf "$out/noise.tar.gz" -T -) || true
  for work in /tmp/device_noise/*; do
    [ -f "$work/noise_study.json" ] && python3 scripts/calibration_summary.py "$(basename "$work")=$work/noise_study.json"
  done | tee "$out/noise.txt"
}

# The sampler at its defaults: ASSET's scene without its likelihood and sampler blocks, on
# full-size photographs at σ 16; one summary line appended to OUT/run.txt.
default_run() {  # VKRECON ASSET OUT
  local vk=$1 name=$2 out=$3 start=$SECONDS
  local images=$out/${name}_images scene=assets/$name/scene_defaults.json
  python3 -c 'import json, sys
s = json.load(open(sys.argv[1])); s.pop("likelihood", None); s.pop("sampler", None)
json.dump(s, open(sys.argv[2], "w"), indent=2)' "assets/$name/scene.json" "$scene"
  $vk synth "assets/$name/scene.json" --at "assets/$name/truth.json" --noise 16 --seed 1 -q -o "$images"
  # shellcheck disable=SC2086
  timeout 400 $vk run "$scene" -q ${DEVICE_CHECK_DEFAULT_ARGS:-} --set cameras="$images/cameras.json" \
    --set images="$images" -o "$out/${name}_run" >/dev/null 2>&1 || true
  python3 -c 'import json, statistics, sys
m, t, s = (json.load(open(p)) for p in sys.argv[1:4])
e = [abs(v["map"] - t[k]) / (s["parameters"][k]["prior"]["uniform"][1] - s["parameters"][k]["prior"]["uniform"][0])
     for k, v in m["parameters"].items()]
c = sum(v["q025"] <= t[k] <= v["q975"] for k, v in m["parameters"].items())
print("default", sys.argv[4], json.dumps(m["sampling"]), "iterations", m["iterations"], "evaluations",
      m["evaluations"], "median_error", statistics.median(e), "covered", c, len(e), "verdict",
      m["diagnosis"]["verdict"], "wall_s", sys.argv[5])' "$out/${name}_run/map.json" "assets/$name/truth.json" \
    "assets/$name/scene.json" "$name" "$((SECONDS - start))" >>"$out/run.txt" 2>&1 || echo "default $name: failed" >>"$out/run.txt"
  tail -1 "$out/run.txt"
  rm -rf "$images" "$out/${name}_run" "$scene"
}

case "${1:-}" in
  prepare) prepare ;;
  run) shift; DEVICE_CHECK_BENCH_ARGS=("${@:2}"); run "$1" ;;
  *) echo "usage: scripts/device_check.sh prepare | run OUT [bench options]" >&2; exit 2 ;;
esac
