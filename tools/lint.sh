#!/usr/bin/env bash
# Lint the Fortran sources: `fortitude check` with the rules of fortitude.toml, and the file
# naming convention (a file holding a module is named after it: module foo -> src/foo.f90 or
# src/foo.F90). Exits non-zero on any finding.
# Usage: tools/lint.sh [FILES or DIRS...]   (default: src/)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

fortitude=.venv/bin/fortitude
if [[ ! -x $fortitude ]]; then
    echo "lint: $fortitude not found: run 'make deps' (tools/deps.sh) first" >&2
    exit 2
fi

targets=("$@")
((${#targets[@]})) || targets=(src/)

status=0
if ! "$fortitude" check --config fortitude.toml --output-format concise "${targets[@]}"; then
    status=1
    echo "lint: many of these are fixed by '$fortitude check --fix ${targets[*]}'" >&2
fi

# module name == file name (fortitude has no rule for it); S211 already forbids two modules a file
shopt -s nullglob
files=()
for t in "${targets[@]}"; do
    if [[ -d $t ]]; then files+=("${t%/}"/*.f90 "${t%/}"/*.F90); else files+=("$t"); fi
done
for f in "${files[@]}"; do
    [[ $f == *.f90 || $f == *.F90 ]] || continue
    base=$(basename "$f"); base=${base%.*}
    name=$(awk 'tolower($0) ~ /^[ \t]*(module|submodule[ \t]*\([^)]*\))[ \t]+[a-z_][a-z0-9_]*[ \t]*(!.*)?$/ {
                  line = tolower($0); sub(/!.*/, "", line); n = split(line, w, /[ \t)]+/)
                  print w[n] == "" ? w[n-1] : w[n]; exit }' "$f")
    if [[ -n $name && $name != "${base,,}" ]]; then
        echo "$f:1:1: NAME module '$name' is not in a file named after it ($name.f90 or $name.F90)"
        status=1
    fi
done

exit "$status"
