#!/usr/bin/env bash
# Benchmarks vkrecon on this machine's Vulkan device (thesis appendix A) and regenerates
# bench/RESULTS.md: builds vkrecon if needed, runs `vkrecon bench --json --plots bench/`,
# keeps the numbers as bench/results-<device>.json and writes the tables, the plots and
# the analysis of the run into RESULTS.md. Extra arguments go to `vkrecon bench`
# (e.g. --quick, --only house, --device 1). Takes a few minutes on a 2-core CPU machine.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh vkrecon >&2
VKRECON=${VKRECON_BUILD_DIR:-build}/apps/vkrecon

command=("$VKRECON" bench --json --plots bench "$@")
shown="vkrecon bench --json --plots bench${*:+ $*}"
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
"${command[@]}" >"$tmp"
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

# Add how the run was made, then name the file after the device.
json=$(python3 - "$tmp" "$started" "$load_before" "$load_after" "$shown" <<'PY'
import json, os, platform, re, sys
path, started, before, after, command = sys.argv[1:6]
with open(path) as f:
    results = json.load(f)
cpu = ""
try:
    with open("/proc/cpuinfo") as f:
        cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "")
except OSError:
    pass
results["run"] = {"date": started, "command": command, "cpu": cpu, "cores": os.cpu_count(),
                  "kernel": platform.release(), "load_before": before, "load_after": after}
slug = re.sub(r"[^a-z0-9]+", "-", results["device"].lower()).strip("-")
out = os.path.join("bench", f"results-{slug}.json")
with open(out, "w") as f:
    json.dump(results, f, indent=2)
    f.write("\n")
print(out)
PY
)
python3 bench/report.py "$json" >bench/RESULTS.md
# The Peers section comes from its own, much longer run (bench/peers.sh): put it back.
# Debian's python3 has python3-matplotlib (bootstrap.sh plots) for the figure; another
# python3 first on PATH (pyenv) may not.
python=/usr/bin/python3
[ -x "$python" ] || python=python3
if [ -f bench/peers.json ]; then "$python" bench/peers_report.py bench/peers.json; fi
# So does the Sampler section (bench/sampler.sh's rows, kept in bench/sampler.md): its
# default runs take minutes each.
if [ -f bench/sampler.md ]; then
  { echo; echo "<!-- sampler -->"; cat bench/sampler.md; echo "<!-- /sampler -->"; } >>bench/RESULTS.md
fi
# So do the GPU sections, measured on lent machines (scripts/device_check.sh).
for d in bench/gpu/*/; do
  if [ -f "$d/machine.txt" ]; then python3 bench/device_report.py "$d"; fi
done
echo "bench/run.sh: wrote $json and bench/RESULTS.md" >&2
