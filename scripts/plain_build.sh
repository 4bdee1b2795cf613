#!/usr/bin/env bash
# Builds the libraries and the binary without unity batches, and every header on its own,
# into build-plain/ (or $VKRECON_PLAIN_BUILD_DIR). scripts/build.sh unity-builds for speed,
# which hides a header that uses what it does not include (a batch's earlier file included
# it); CI runs this once so that stays fixed. Installs nothing: scripts/bootstrap.sh does.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${VKRECON_PLAIN_BUILD_DIR:-build-plain}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVKRECON_UNITY=OFF \
  -DVKRECON_HEADER_CHECK=ON -DBUILD_TESTING=OFF >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)" --target vkrecon header_check
echo "plain build: every library, the binary and every header alone compile without unity" >&2
