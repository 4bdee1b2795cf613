#!/usr/bin/env bash
# The installed library works from another project: installs BUILD into a prefix, builds
# tests/install/consumer against it with find_package(vkrecon), and checks that it scores
# the bundled house exactly as the installed `vkrecon likelihood` does (same double).
# Usage: tests/install/check.sh BUILD_DIR
set -euo pipefail
build=$(cd "${1:?usage: check.sh BUILD_DIR}" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
work=$build/install-check
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$here/consumer" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/consumer" >/dev/null

vk=$work/prefix/bin/vkrecon
asset=$work/prefix/share/vkrecon/assets/house
"$vk" synth "$asset/scene.json" --at "$asset/truth.json" --scale 0.25 --noise 8 --seed 1 -q -o "$work/images"
sets=(cameras="$work/images/cameras.json" images="$work/images" likelihood.atlas=128)
cli=$("$vk" likelihood "$asset/scene.json" --at "$asset/truth.json" -q "${sets[@]/#/--set=}" |
      awk '$1 == "total" {print $2}')
lib=$("$work/consumer/consumer" "$asset/scene.json" "$asset/truth.json" "${sets[@]}")
echo "vkrecon likelihood: $cli"
echo "consumer:           $lib"
python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) == float(sys.argv[2]) else 1)' "$cli" "$lib" ||
  { echo "check.sh: the installed library and the installed binary disagree" >&2; exit 1; }
