#!/usr/bin/env bash
# Configures and builds vkrecon into build/ (or $VKRECON_BUILD_DIR) with Ninja.
# Installs nothing: scripts/bootstrap.sh does that. Usage: scripts/build.sh [TARGET…]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${VKRECON_BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVKRECON_UNITY=ON >/dev/null
# Arguments name targets (e.g. `vkrecon`); none builds everything.
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$BUILD_DIR" -j "$(nproc)" "${targets[@]}"
