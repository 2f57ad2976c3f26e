#!/usr/bin/env bash
# Open an MBSPH XDMF index in ParaView (headless, under Xvfb) and print what ParaView sees as
# one JSON line: time steps, points, point arrays and the (min, max) of one array.
# Usage: tools/pv_probe.sh OUT/particles.xmf ARRAY [--time T] [--screenshot FILE.png]
# Needs Debian's paraview, python3-paraview, xvfb (tools/deps.sh installs them).
set -euo pipefail

if (($# < 2)); then
    echo "usage: $0 OUT/particles.xmf ARRAY [--time T] [--screenshot FILE.png]" >&2
    exit 2
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
for tool in pvpython xvfb-run xauth; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "pv_probe: $tool not found: run tools/deps.sh without MBSPH_NO_PARAVIEW=1" >&2
        exit 2
    fi
done

out=$(mktemp)
trap 'rm -f "$out"' EXIT
status=0
# 24-bit screen: xvfb-run's default 8-bit one is no good for OpenGL rendering
xvfb-run -a -s "-screen 0 1280x1024x24" \
    pvpython --force-offscreen-rendering "$root/tests/pv_check.py" "$@" >"$out" </dev/null || status=$?
# pvpython may print other lines on stdout: the JSON is the last line that starts with '{'
json=$(grep '^{' "$out" | tail -n 1 || true)
if [[ -z $json ]]; then
    cat "$out" >&2
    echo "pv_probe: ParaView printed no result (exit status $status)" >&2
    exit $((status ? status : 1))
fi
printf '%s\n' "$json"
exit "$status"
