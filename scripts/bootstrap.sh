#!/usr/bin/env bash
# Installs exactly the Debian packages vkrecon needs, from the compiler up.
# Idempotent: runs `apt-get update` and `apt-get install` only when something is missing.
# Works as root or through sudo; a bare Debian 12 with nothing but apt is enough.
# Usage: scripts/bootstrap.sh [GROUP…]. Optional groups add packages a few scripts need:
#   fuzz    clang, libFuzzer and llvm-symbolizer for scripts/fuzz.sh (docs/internals/FUZZING.md)
#   report  headless Chromium for scripts/report_screenshot.sh (docs/guide/REPORT.md)
#   plots   matplotlib for the figure of bench/peers_report.py (bench/RESULTS.md, "Peers")
#   python  pybind11, numpy and pytest for `import vkrecon` and its tests (docs/guide/PYTHON.md);
#           emcee for bench/peers/emcee_peer.py
#   colmap  COLMAP for scripts/calibrate.sh, photographs to the sparse model `vkrecon init` reads
set -euo pipefail

PACKAGES=(
  # toolchain
  g++ cmake ninja-build ccache pkg-config git ca-certificates
  # Vulkan: loader + headers, Mesa lavapipe (the CPU device), validation layer, shader compiler
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools
  # libraries
  libeigen3-dev libopenexr-dev libtinygltf-dev nlohmann-json3-dev libstb-dev
  libcli11-dev libmuparser-dev libgtest-dev
  # NLopt (C++ header + libraries; pulls libnlopt-dev and the runtimes): `vkrecon fit`, the
  # peers benchmark and run's polish of the MAP (optimiser/MapSearch.h)
  libnlopt-cxx-dev
  # python3 draws the plots of the sweep and benchmark scripts (optional at run time)
  python3
  # the plots and the 3D view of a run's report.html, inlined from /usr/share/javascript
  # (optional at run time: without them the report keeps its tables and images; docs/guide/REPORT.md)
  libjs-chart.js libjs-three
  # MPI: `mpirun -n R vkrecon run` spreads a run over R ranks, one Vulkan device each
  # (optional at configure time: without it vkrecon builds and runs as one process;
  # docs/guide/SCALE_OUT.md)
  libopenmpi-dev openmpi-bin
)

for group in "$@"; do
  case "$group" in
    # clang-14 is Debian 12's clang; libclang-rt-14-dev holds libFuzzer and the sanitizer
    # runtimes, llvm-14 the symbolizer that turns their reports into file:line.
    fuzz) PACKAGES+=(clang-14 libclang-rt-14-dev llvm-14) ;;
    # chromium renders report.html headless: a screenshot, and the page's console errors.
    report) PACKAGES+=(chromium) ;;
    plots) PACKAGES+=(python3-matplotlib) ;;
    # pybind11 and Debian's python3 build `import vkrecon` (python/); numpy and pytest run it;
    # emcee is the sampler's peer on the same likelihood (bench/peers/emcee_peer.py)
    python) PACKAGES+=(pybind11-dev python3-dev python3-numpy python3-pytest python3-emcee) ;;
    colmap) PACKAGES+=(colmap) ;;
    *) echo "bootstrap: unknown package group '$group' (known: fuzz, report, plots, python, colmap)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${PACKAGES[@]}"; do
  # dpkg-query prints "install ok installed" only for a fully installed package.
  if [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" != "install ok installed" ]; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "bootstrap: all ${#PACKAGES[@]} packages present" >&2
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "bootstrap: missing packages (${missing[*]}) and neither root nor sudo available" >&2
  exit 1
fi

echo "bootstrap: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
