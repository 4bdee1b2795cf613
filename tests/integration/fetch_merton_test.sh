#!/usr/bin/env bash
# scripts/fetch_merton.sh: a copy that does not check is refused (exit 2, one line naming the
# file), a bad usage too; with the photographs beside the clone (../shared/data), they are
# copied and checked. Without them that part is skipped: a download needs the network.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
fetch=$root/scripts/fetch_merton.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$fetch" >/dev/null 2>&1
[ $? -eq 2 ] || fail "no argument: expected exit 2"

mkdir -p "$work/bad"
for name in 001.jpg 002.jpg 003.jpg; do echo "not a photograph" > "$work/bad/$name"; done
message=$(VKRECON_MERTON=$work/bad "$fetch" "$work/out" 2>&1)
status=$?
[ $status -eq 2 ] || fail "a copy that does not check: exit $status, expected 2 ($message)"
[ "$(printf '%s\n' "$message" | wc -l)" -eq 1 ] || fail "expected one line, got: $message"
case $message in *"$work/out/001.jpg: its SHA-256 is not the dataset's"*) ;; *) fail "unexpected message: $message" ;; esac

if [ -d "$root/../shared/data/merton_college_1/images" ]; then
  "$fetch" "$work/photos" 2>/dev/null || fail "the local copy: exit $?"
  for name in 001.jpg 002.jpg 003.jpg; do [ -s "$work/photos/$name" ] || fail "$name not copied"; done
  "$fetch" "$work/photos" 2>/dev/null || fail "a second fetch over checked files: exit $?"
else
  echo "fetch_merton_test: no local copy beside the clone; the copy is not tried" >&2
fi
echo "fetch_merton_test: ok"
