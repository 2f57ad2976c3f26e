#!/usr/bin/env bash
# Lint the Fortran sources: `fortitude check` with the rules of fortitude.toml, the file
# naming convention (a file holding a module is named after it: module foo -> src/foo.f90 or
# src/foo.F90), and the included fragments src/*.inc as the preprocessor expands them.
# Exits non-zero on any finding.
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

# The cpp fragments (src/*.inc) and the code generated from src/*.fypp are no Fortran units
# of their own: lint them as the compiler sees them, each .F90 expanded with its includes and
# switches (every variant of the pair loops). Line length is checked on the fragments themselves (an expanded macro makes long
# lines), and an `allow` on an #include line has nothing left to allow once it is expanded.
if ((${#@} == 0)); then
    expanded=$(mktemp -d)
    trap 'rm -rf "$expanded"' EXIT
    # the generated fragments as make writes them (Makefile: GEN)
    mkdir -p "$expanded/gen"
    ndim=$(sed -n 's/^ *integer, parameter :: ndim = \([0-9]\) .*/\1/p' src/constants.f90)
    fypp() { .venv/bin/fypp -DNDIM="$ndim" "$@"; }
    fypp -DPART="'loops'" src/fluid_variants.fypp "$expanded/gen/fluid_variants.inc"
    fypp -DPART="'dispatch'" src/fluid_variants.fypp "$expanded/gen/fluid_dispatch.inc"
    fypp -DPART="'body'" src/pre_pairs.fypp "$expanded/gen/pre_pairs.inc"
    fypp -DPART="'decl'" src/pre_pairs.fypp "$expanded/gen/pre_decl.inc"
    for f in mdbc_ghosts nbr_pairs shepard_pairs contact_pairs; do
        fypp "src/$f.fypp" "$expanded/gen/$f.inc"
    done
    for part in decl table slots; do
        fypp -DPART="'$part'" src/particle_fields.fypp "$expanded/gen/particle_$part.inc"
    done
    for f in src/*.F90; do
        if ! gfortran -E -cpp -P -Isrc -I"$expanded/gen" "$f" > "$expanded/$(basename "${f%.F90}").f90"; then
            echo "$f:1:1: CPP the preprocessor refused it"
            status=1
        fi
    done
    if ! "$fortitude" check --config fortitude.toml --output-format concise \
            --extend-per-file-ignores "*.f90:FORT002" --extend-per-file-ignores "*.f90:S001" "$expanded"/*.f90; then
        echo "lint: the findings above are in src/*.F90 with their src/*.inc expanded" >&2
        status=1
    fi
    for f in src/*.inc src/*.fypp; do
        awk -v f="$f" 'length($0) > 132 { printf "%s:%d:133: S001 line length of %d, exceeds maximum 132\n", f, NR, length($0); bad = 1 }
                       END { exit bad }' "$f" || status=1
    done
fi

exit "$status"
