#!/usr/bin/env bash
# The peers benchmark (issue 15): `vkrecon run` against NLopt's methods at finding the MAP,
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
"$VKRECON" bench --only peers --json "$@" >"$tmp"
mv "$tmp" bench/peers.json
# Debian's python3 has python3-matplotlib (bootstrap.sh plots) for the figure; another
# python3 first on PATH (pyenv) may not (bench/run.sh does the same).
python=/usr/bin/python3
[ -x "$python" ] || python=python3
"$python" bench/peers_report.py bench/peers.json
