#!/usr/bin/env bash
# Installs what is missing, builds, and runs the bundled `house` example: renders its
# reference photographs from the true parameters (vkrecon synth), then novel views on a
# ring around it (vkrecon render). Outputs land in out/house/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/bootstrap.sh
scripts/build.sh vkrecon
VKRECON=${VKRECON_BUILD_DIR:-build}/apps/vkrecon
ASSET=assets/house
OUT=out/house
mkdir -p "$OUT"

echo "== 1/2 synth: reference images of $ASSET at its truth (noise σ = 8)"
"$VKRECON" synth "$ASSET/scene.json" --at "$ASSET/truth.json" --noise 8 --seed 1 -o "$ASSET/images"

echo "== 2/2 render: 8 novel views on an orbit, linear float EXR + PNG previews"
"$VKRECON" render "$ASSET/scene.json" --at "$ASSET/truth.json" --orbit 8 --png -o "$OUT/orbit.exr"

echo
echo "Reference images:  $ASSET/images/*.png  (+ cameras.json)"
echo "Novel views:       $OUT/orbit_*.exr (open in any EXR viewer or Blender), $OUT/orbit_*.png"
