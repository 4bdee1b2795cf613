#!/usr/bin/env bash
# Opens a run's report.html in headless Chromium, saves a screenshot, and fails when the page
# reports an error. The page records every uncaught error, failed resource and console.error
# in its #report-errors list (report/error_hook.js), which the DOM dump shows; it also marks
# <body> once its plots are drawn, so a script that never ran is caught too. It checks
# `vkrecon preview`'s preview.html the same way (its wireframes drawn, data-preview="drawn").
# Usage: scripts/report_screenshot.sh PAGE.html[#FRAGMENT] SCREENSHOT.png [DOM.html]
# (the fragment goes to the page, e.g. preview.html's slider values; DOM.html keeps the DOM dump).
# Exit status: 0 clean, 1 page errors (listed on stderr) or Chromium failed, 2 usage,
# 77 Chromium not installed (ctest's SKIP_RETURN_CODE; `scripts/bootstrap.sh report` installs it).
set -euo pipefail
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: $0 PAGE.html[#FRAGMENT] SCREENSHOT.png [DOM.html]" >&2
  exit 2
fi
fragment=""
[[ "$1" == *"#"* ]] && fragment="#${1#*#}"
report=$(realpath -m "${1%%#*}")
shot=$2
keep_dom=${3:-}
if [ ! -f "$report" ]; then
  echo "report_screenshot: $1: no such file" >&2
  exit 2
fi
CHROMIUM=${CHROMIUM:-$(command -v chromium || command -v chromium-browser || true)}
if [ -z "$CHROMIUM" ] || [ ! -x "$CHROMIUM" ]; then
  echo "report_screenshot: skipped: chromium is not installed (scripts/bootstrap.sh report installs it)" >&2
  exit 77
fi

profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# SwiftShader gives the headless browser WebGL without a GPU, so the 3D view runs as well.
# The virtual time budget lets the scripts finish before the DOM is dumped and the shot taken.
flags=(--headless --disable-gpu --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader
       --user-data-dir="$profile" --hide-scrollbars --virtual-time-budget=15000 --window-size=1280,2400)
dom="$profile/dom.html"
if ! timeout 180 "$CHROMIUM" "${flags[@]}" --dump-dom "file://$report$fragment" >"$dom" 2>"$profile/log"; then
  echo "report_screenshot: chromium failed on $report:" >&2
  tail -5 "$profile/log" >&2
  exit 1
fi
status=0
if grep -q 'class="report-error"' "$dom"; then
  echo "report_screenshot: $report reports errors:" >&2
  grep -o '<li class="report-error">[^<]*' "$dom" | sed 's/<li class="report-error">/  /' >&2
  status=1
fi
# Chart.js inlined (its banner is in the page) but the plots never drawn: the script stopped.
if grep -q 'Chart.js v' "$report" && ! grep -q 'data-report-charts="drawn"' "$dom"; then
  echo "report_screenshot: $report: the plots were not drawn (its script did not finish)" >&2
  status=1
fi
# A preview page whose script stopped before it drew.
if grep -q 'id="preview-data"' "$report" && ! grep -q 'data-preview="drawn"' "$dom"; then
  echo "report_screenshot: $report: the wireframes were not drawn (its script did not finish)" >&2
  status=1
fi
[ -n "$keep_dom" ] && cp "$dom" "$keep_dom"
mkdir -p "$(dirname "$shot")"
if ! timeout 180 "$CHROMIUM" "${flags[@]}" --screenshot="$(realpath -m "$shot")" "file://$report$fragment" 2>>"$profile/log" >/dev/null; then
  echo "report_screenshot: chromium could not take the screenshot:" >&2
  tail -5 "$profile/log" >&2
  exit 1
fi
[ $status -eq 0 ] && echo "report_screenshot: $shot (no errors in the page)" >&2
exit $status
