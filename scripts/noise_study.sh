#!/usr/bin/env bash
# Accuracy and coverage of reconstructions against image noise (thesis Fig 4.15): builds
# vkrecon, then runs scripts/noise_study.py with every argument passed on (`--help` explains
# them). A developer tool: it does not call scripts/bootstrap.sh, so the build dependencies
# must already be installed (run scripts/demo.sh or scripts/test.sh once for that).
#   scripts/noise_study.sh                      # full study → docs/internals/NOISE_STUDY.md (~40 min on 2 cores)
#   scripts/noise_study.sh --quick --assets box --sigmas 0,16 --work /tmp/ns \
#       --report /tmp/ns/report.md --plot /tmp/ns/plot.svg
set -euo pipefail
cd "$(dirname "$0")/.."
export NOISE_STUDY_PROG=scripts/noise_study.sh
case " $* " in *" -h "*|*" --help "*) exec python3 scripts/noise_study.py "$@" ;; esac
# Quietly: the build's log is shown (on stderr, away from the report) only when it fails.
echo "noise_study: building vkrecon…" >&2
if ! log=$(scripts/build.sh vkrecon 2>&1); then
  echo "$log" >&2
  exit 1
fi
export VKRECON=${VKRECON_BUILD_DIR:-build}/apps/vkrecon
exec python3 scripts/noise_study.py "$@"
