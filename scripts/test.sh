#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test with the Vulkan validation layer on
# (a validation message fails the test). Usage: scripts/test.sh [ctest arguments…]
set -euo pipefail
cd "$(dirname "$0")/.."
# The report group adds headless Chromium: cli/ReportCli.BrowserFindsNoErrorInThePage opens a
# run's report.html in it (skipped where it is missing, so CI installs it).
# The python group builds `import vkrecon` and runs its pytest suite (python/pytest).
# The colmap group: integration/PhotographsToScene calibrates synthesised photographs with it.
scripts/bootstrap.sh report python colmap
scripts/build.sh
BUILD_DIR=${VKRECON_BUILD_DIR:-build}
export VKRECON_VALIDATION=1
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$(nproc)" "$@"
