#!/usr/bin/env bash
# Builds vkrecon with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ (or
# $VKRECON_ASAN_BUILD_DIR) and runs the whole test suite under them, lavapipe and the
# validation layer included, as scripts/test.sh does. Any sanitizer report fails its test.
# Suppressions (third-party code only) are in scripts/sanitize/; docs/internals/SANITIZERS.md says why.
# Usage: scripts/sanitize.sh [ctest arguments…]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/bootstrap.sh
BUILD_DIR=${VKRECON_ASAN_BUILD_DIR:-build-asan}
SUPP_DIR=$PWD/scripts/sanitize

# -fno-sanitize-recover makes the first UBSan finding abort, so it fails the test instead of
# scrolling past in the log; ASan aborts by default. Frame pointers keep stacks readable.
SAN_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"

# The loader unloads lavapipe at vkDestroyInstance; what lavapipe allocated once for good
# (pthread_once caches) is then reachable from nowhere, and LeakSanitizer reports it with
# frames in an "<unknown module>" that no suppression can name. Linking the driver into our
# executables keeps it mapped to the end, so those blocks stay reachable from its globals.
# It exports only vk_icd* entry points, so it cannot take over our vk* calls.
LVP_ICD=$(ls /usr/share/vulkan/icd.d/lvp_icd.*.json | head -n 1)
LVP_LIB=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' "$LVP_ICD")
[ -f "$LVP_LIB" ] || { echo "sanitize: lavapipe not found via $LVP_ICD" >&2; exit 1; }
KEEP_LVP="-Wl,--push-state,--no-as-needed $LVP_LIB -Wl,--pop-state"

cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVKRECON_UNITY=ON \
  -DCMAKE_CXX_FLAGS="$SAN_FLAGS" -DCMAKE_EXE_LINKER_FLAGS="$SAN_FLAGS $KEEP_LVP" >/dev/null

# Exported before the build too: gtest_discover_tests runs every test binary at build time.
export ASAN_OPTIONS="exitcode=86:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$SUPP_DIR/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="exitcode=86:print_stacktrace=1:halt_on_error=1:suppressions=$SUPP_DIR/ubsan.supp"
cmake --build "$BUILD_DIR" -j "$(nproc)"

export VKRECON_VALIDATION=1
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$(nproc)" "$@"
