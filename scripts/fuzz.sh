#!/usr/bin/env bash
# Fuzzes vkrecon's readers with libFuzzer (docs/internals/FUZZING.md): installs clang and libFuzzer
# when missing, builds the targets of tests/fuzz into build-fuzz (clang, ASan + UBSan),
# runs each for its share of SECONDS, prints a table and exits 1 when anything was found.
# Usage: scripts/fuzz.sh [SECONDS]   (default 600, all targets together)
# Environment: VKRECON_FUZZ_ONLY="a b" runs only those targets.
set -euo pipefail
cd "$(dirname "$0")/.."

TOTAL=${1:-600}
MAX_RESTARTS=50  # per target: a target that fails this often has one bug to fix first
BUILD_DIR=build-fuzz
WORK=$BUILD_DIR/work  # corpora (kept between runs), seeds, crash inputs, logs

scripts/bootstrap.sh fuzz
# RelWithDebInfo at -O1 without NDEBUG: asserts stay on, reports get line numbers.
CC=clang CXX=clang++ cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" -DBUILD_TESTING=OFF -DVKRECON_FUZZ=ON >/dev/null
nice cmake --build "$BUILD_DIR" -j "$(nproc)" --target fuzz_all

# The seeds of each target: the hand-made ones of tests/fuzz/seeds, the inputs the fuzzer
# once crashed on, and the repository's own files of that kind (small ones: libFuzzer's
# input size limit follows the largest seed).
collect_seeds() {
  local name=$1 dir=$WORK/seeds/$1
  rm -rf "$dir"
  mkdir -p "$dir"
  local files=(tests/fuzz/seeds/"$name"/* tests/fuzz/regressions/"$name"/*) limit=65536
  case "$name" in
    scene_json) files+=(assets/*/scene.json assets/*/synth.json docs/examples/*/scene.json) ;;
    at_values) files+=(assets/*/truth.json) ;;
    camera_file) files+=(assets/*/cameras.json) ;;
    # Only the small pictures: the 20-40 KB textures held the image target to ~300 runs/s.
    image) files+=(bench/*.png docs/figures/*.png); limit=16384 ;;
    gltf) files+=(assets/*/meshes/*.glb) ;;
  esac
  local i=0 f
  for f in "${files[@]}"; do
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -le "$limit" ] && cp "$f" "$dir/$((i++))-$(basename "$f")"
  done
  return 0
}

targets=()
for binary in "$BUILD_DIR"/tests/fuzz/fuzz_*; do
  name=${binary##*/fuzz_}
  if [ -n "${VKRECON_FUZZ_ONLY:-}" ] && [[ " $VKRECON_FUZZ_ONLY " != *" $name "* ]]; then continue; fi
  targets+=("$name")
done
per_target=$((TOTAL / ${#targets[@]}))
[ "$per_target" -ge 1 ] || per_target=1

# The readers write their input to files: keep those in memory, and in one folder that
# goes away with this script even when a target crashes.
scratch=$(mktemp -d "$( [ -w /dev/shm ] && echo /dev/shm || echo "${TMPDIR:-/tmp}" )/vkrecon-fuzz.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

mkdir -p "$WORK"
printf '%-12s %12s %8s %8s %6s %10s\n' target executions crashes timeouts ooms sanitizer >"$WORK/table.txt"
total_execs=0
found=0
for name in "${targets[@]}"; do
  collect_seeds "$name"
  corpus=$WORK/corpus/$name
  artifacts=$WORK/artifacts/$name
  log=$WORK/logs/$name.log
  mkdir -p "$corpus" "$artifacts" "$WORK/logs"
  rm -f "$artifacts"/*
  echo "fuzz: $name for ${per_target}s" >&2
  # One libFuzzer process at a time, started again after each crash, hang or out-of-memory
  # until the target's time is up, so all are counted. (Fork mode counts them too but ran
  # at half the executions per second here: docs/internals/FUZZING.md.)
  # -timeout=1: an input that takes a second is a hang. -malloc_limit_mb: one allocation
  # over 1 GiB from a file of at most 64 KiB is a header believed too readily.
  : >"$log"
  execs=0
  deadline=$((SECONDS + per_target))
  for attempt in $(seq 1 "$MAX_RESTARTS"); do
    left=$((deadline - SECONDS))
    [ "$left" -ge 1 ] || break
    status=0
    TMPDIR=$scratch "$BUILD_DIR/tests/fuzz/fuzz_$name" -max_total_time="$left" -timeout=1 \
      -rss_limit_mb=2560 -malloc_limit_mb=1024 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$artifacts/" "$corpus" "$WORK/seeds/$name" >"$log.run" 2>&1 || status=$?
    cat "$log.run" >>"$log"
    # Executions of this run: the final statistics, or the last status line before a crash.
    n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log.run" | tail -1)
    [ -n "$n" ] || n=$(grep -oE '^#[0-9]+' "$log.run" | tail -1 | tr -d '#')
    execs=$((execs + ${n:-0}))
    [ "$status" -eq 0 ] && break
  done
  rm -f "$log.run"
  crashes=$(find "$artifacts" -name 'crash-*' | wc -l)
  timeouts=$(find "$artifacts" -name 'timeout-*' | wc -l)
  ooms=$(find "$artifacts" -name 'oom-*' | wc -l)
  sanitizer=$(grep -cE '^SUMMARY: (Address|UndefinedBehavior|Leak)Sanitizer' "$log" || true)
  printf '%-12s %12s %8s %8s %6s %10s\n' "$name" "$execs" "$crashes" "$timeouts" "$ooms" "$sanitizer" >>"$WORK/table.txt"
  total_execs=$((total_execs + execs))
  found=$((found + crashes + timeouts + ooms + sanitizer))
done
printf '%-12s %12s\n' total "$total_execs" >>"$WORK/table.txt"
cat "$WORK/table.txt"
if [ "$found" -gt 0 ]; then
  echo "fuzz: found inputs that crash, hang or exhaust memory: $WORK/artifacts/*/ (logs: $WORK/logs/)" >&2
  exit 1
fi
