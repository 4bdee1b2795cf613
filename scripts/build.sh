#!/usr/bin/env bash
# Configures and builds vkrecon into build/ (or $VKRECON_BUILD_DIR) with Ninja.
# Installs nothing: scripts/bootstrap.sh does that.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${VKRECON_BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)"
