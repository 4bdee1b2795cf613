#!/usr/bin/env bash
# The Debian package on a bare Debian 12: debootstrap a minimal bookworm into a folder, install
# the package there with apt (which pulls its dependencies), then `vkrecon devices`, synth and
# a short run of the bundled box. Needs root and Debian's mirror; about 10 minutes. Not part
# of the tests (docs/reference/LIBRARY.md). Usage: scripts/check_deb.sh build/vkrecon_*.deb [ROOT]
set -euxo pipefail
deb=$(realpath "${1:?usage: scripts/check_deb.sh PACKAGE.deb [ROOT]}")
root=${2:-/tmp/vkrecon-deb12}
command -v debootstrap >/dev/null || apt-get install -y -qq debootstrap
rm -rf "$root"
debootstrap --variant=minbase bookworm "$root" http://deb.debian.org/debian
cp "$deb" "$root/tmp/"
mount -t proc proc "$root/proc"
trap 'umount "$root/proc"' EXIT
in_root() { chroot "$root" env DEBIAN_FRONTEND=noninteractive "$@"; }
in_root apt-get update -qq
in_root apt-get install -y -qq "/tmp/$(basename "$deb")"
in_root vkrecon devices
assets=/usr/share/vkrecon/assets
in_root vkrecon synth $assets/box/scene.json --at $assets/box/truth.json --scale 0.25 --noise 8 -q -o /tmp/box
in_root vkrecon run $assets/box/scene.json --set images=/tmp/box --set cameras=/tmp/box/cameras.json \
  --set likelihood.atlas=128 --time-limit 30 -q -o /tmp/box_run
in_root test -s /tmp/box_run/map.json
echo "check_deb: the package installs and runs on a bare Debian 12"
