#!/usr/bin/env bash
# Fetches the tutorial's photographs (docs/guide/OWN_PHOTOGRAPHS.md): three 1024×768 JPEGs of
# the inside corner of a courtyard at Merton College, Oxford, from the Oxford Visual Geometry
# Group's multi-view data (https://www.robots.ox.ac.uk/~vgg/data/mview/), as the public
# repository matteo-bruni/binocular-dense-stereo keeps them. No licence travels with them: for
# research and testing; they are not part of this repository.
#   scripts/fetch_merton.sh PHOTOS/   →   PHOTOS/001.jpg 002.jpg 003.jpg, checked by SHA-256
# Copies them from a local copy when there is one (VKRECON_MERTON, or ../shared/data beside
# the clone), else downloads them with curl or wget.
# Exit status: 0 done, 2 bad usage, nothing to download with or a file that does not check.
set -euo pipefail

if [ $# -ne 1 ]; then
  echo "usage: scripts/fetch_merton.sh PHOTOS/" >&2
  exit 2
fi
dest=${1%/}
root=$(cd "$(dirname "$0")/.." && pwd)
local_copy=${VKRECON_MERTON:-$root/../shared/data/merton_college_1/images}
url=https://raw.githubusercontent.com/matteo-bruni/binocular-dense-stereo/073a9be9f22a1055f47396ed272a4de201e67f44/dataset_merton/images
declare -A sha256=(
  [001.jpg]=b3391a8f43431711addc19a44621f63c13cefb02eadc441f458545929b9d0c79
  [002.jpg]=1ca10d7192bb03707e82b880de903abb5b69ecb4d251c145bb84d8ba481f6f2a
  [003.jpg]=7dc84c685bf57e08dd570b8a8e233add036840ac154618884cd0b43f724ef105
)

checks() { [ -f "$1" ] && [ "$(sha256sum "$1" | cut -d' ' -f1)" = "$2" ]; }

download() {
  if command -v curl >/dev/null 2>&1; then
    curl -fsSL --retry 2 -o "$2" "$1"
  elif command -v wget >/dev/null 2>&1; then
    wget -q -O "$2" "$1"
  else
    echo "fetch_merton: neither curl nor wget is installed (sudo apt-get install curl)" >&2
    exit 2
  fi
}

mkdir -p "$dest"
for name in 001.jpg 002.jpg 003.jpg; do
  file=$dest/$name
  if checks "$file" "${sha256[$name]}"; then
    continue
  elif [ -f "$local_copy/$name" ]; then
    install -m 644 "$local_copy/$name" "$file"
  else
    echo "fetch_merton: downloading $name" >&2
    download "$url/$name" "$file.part" || { rm -f "$file.part"; echo "fetch_merton: $url/$name: download failed" >&2; exit 2; }
    mv "$file.part" "$file"
  fi
  if ! checks "$file" "${sha256[$name]}"; then
    echo "fetch_merton: $file: its SHA-256 is not the dataset's (a changed or truncated copy); remove it and retry" >&2
    exit 2
  fi
done
echo "fetch_merton: $dest/001.jpg 002.jpg 003.jpg (Oxford VGG, Merton College I; research and testing only)" >&2
