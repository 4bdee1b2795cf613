#!/usr/bin/env bash
# Calibrates a folder of photographs with Debian's COLMAP on the CPU (no CUDA needed), for
# `vkrecon init` (docs/guide/REAL_PHOTOS.md):
#   scripts/calibrate.sh PHOTOS/ SPARSE/   →   SPARSE/database.db, SPARSE/0/{cameras,images,points3D}.bin
# SIFT features (no GPU), exhaustive matching (fine for the tens of photographs of one object),
# then incremental mapping. One camera for all photographs unless VKRECON_COLMAP_CAMERAS=per_image;
# the model is SIMPLE_RADIAL unless VKRECON_COLMAP_MODEL names another that vkrecon reads
# (PINHOLE, SIMPLE_PINHOLE, RADIAL, OPENCV, FULL_OPENCV). A masks/ folder beside PHOTOS
# (COLMAP's project layout, docs/guide/SCENE_FORMAT.md "Masks") keeps masked pixels out of the features.
# Exit status: 0 done, 2 bad input or COLMAP missing (one line), 1 COLMAP failed.
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: scripts/calibrate.sh PHOTOS/ SPARSE/" >&2
  exit 2
fi
photos=${1%/}
sparse=${2%/}
if ! command -v colmap >/dev/null 2>&1; then
  echo "calibrate: colmap is not installed (scripts/bootstrap.sh colmap installs Debian's)" >&2
  exit 2
fi
if [ ! -d "$photos" ]; then
  echo "calibrate: $photos: not a folder of photographs" >&2
  exit 2
fi
if [ -e "$sparse/database.db" ]; then
  echo "calibrate: $sparse/database.db: exists; calibrate does not overwrite (remove $sparse or choose another)" >&2
  exit 2
fi
mkdir -p "$sparse"
log="$sparse/colmap.log"

extract=(--database_path "$sparse/database.db" --image_path "$photos"
         --ImageReader.camera_model "${VKRECON_COLMAP_MODEL:-SIMPLE_RADIAL}"
         --SiftExtraction.use_gpu 0)
[ "${VKRECON_COLMAP_CAMERAS:-single}" = per_image ] || extract+=(--ImageReader.single_camera 1)
[ -d "$photos/../masks" ] && extract+=(--ImageReader.mask_path "$photos/../masks")

step() {
  echo "calibrate: $1" >&2
  shift
  if ! "$@" >>"$log" 2>&1; then
    echo "calibrate: colmap $2 failed (its output: $log)" >&2
    exit 1
  fi
}
step "1/3 features (SIFT on the CPU)" colmap feature_extractor "${extract[@]}"
step "2/3 matching (exhaustive)" colmap exhaustive_matcher --database_path "$sparse/database.db" --SiftMatching.use_gpu 0
# A model of a few photographs is kept: mapper drops those under 10 images by default.
step "3/3 mapping" colmap mapper --database_path "$sparse/database.db" --image_path "$photos" --output_path "$sparse" \
  --Mapper.min_model_size 3

if [ ! -f "$sparse/0/cameras.bin" ]; then
  echo "calibrate: COLMAP registered no model (too few matches between the photographs? see $log)" >&2
  exit 1
fi
models=$(find "$sparse" -mindepth 1 -maxdepth 1 -type d | wc -l)
[ "$models" -gt 1 ] && echo "calibrate: COLMAP made $models separate models; $sparse/0 is the first (usually the largest)" >&2
echo "calibrate: done. Next: vkrecon init $sparse/0 -o SCENE/ --images $photos" >&2
