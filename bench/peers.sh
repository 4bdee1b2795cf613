#!/usr/bin/env bash
# The peers benchmark: `vkrecon run` against NLopt's methods at finding the MAP,
# 4 assets × 5 seeds at σ = 16 (~45 min on 2 cores). Keeps bench/peers.json and splices the
# "Peers" section (table, bench/peers.png, bench/peers_notes.md) into bench/RESULTS.md,
# leaving the throughput sections as they are. Extra arguments go to `vkrecon bench`
# (e.g. --quick, --work DIR; after a crash or an interruption, the same command with
# --work DIR --resume keeps the groups already in DIR/peers.json and runs the rest).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh vkrecon >&2
VKRECON=${VKRECON_BUILD_DIR:-build}/apps/vkrecon
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
# A work folder unless one is given, so that a crash costs one (asset, seed) group: lavapipe
# has a rare heap race (docs/internals/HARDENING.md, "A rare crash inside lavapipe"); after SIGSEGV or
# SIGABRT the bench goes on with --resume, at most twice.
work=(--work build/peers-work)
for arg in "$@"; do [ "$arg" = --work ] && work=(); done
resume=()
for attempt in 1 2 3; do
  status=0
  "$VKRECON" bench --only peers --json "${work[@]}" "${resume[@]}" "$@" >"$tmp" || status=$?
  [ "$status" -eq 139 ] || [ "$status" -eq 134 ] || break
  [ "$attempt" -lt 3 ] && echo "bench/peers.sh: vkrecon died (status $status); going on with --resume" >&2
  resume=(--resume)
done
[ "$status" -eq 0 ] || exit "$status"
mv "$tmp" bench/peers.json
# Debian's python3 has python3-matplotlib (bootstrap.sh plots) for the figure; another
# python3 first on PATH (pyenv) may not (bench/run.sh does the same).
python=/usr/bin/python3
[ -x "$python" ] || python=python3
"$python" bench/peers_report.py bench/peers.json
