#!/usr/bin/env bash
# Writes make dependencies for Fortran sources: one module per file, named
# after the module, so "use X" in a file means its object needs X.o.
# Usage: tools/fdeps.sh OBJDIR file...   (prints rules on stdout)
set -eu
objdir=$1; shift
for f in "$@"; do
  base=$(basename "${f%.*}")
  deps=""
  for m in $(grep -ioE '^[[:space:]]*use[[:space:]]*(,[[:space:]]*[a-z_]+[[:space:]]*::)?[[:space:]]*[a-z0-9_]+' "$f" \
             | sed -E 's/.*[[:space:]:]([A-Za-z0-9_]+)$/\1/' | tr 'A-Z' 'a-z' | sort -u); do
    [ "$m" = "$base" ] && continue
    if [ -e "src/$m.f90" ] || [ -e "src/$m.F90" ]; then deps="$deps $objdir/$m.o"; fi
  done
  for i in $(grep -oE '^#include[[:space:]]+"[^"]+"' "$f" | sed -E 's/.*"(.*)"/\1/'); do
    deps="$deps src/$i"
    for j in $(grep -oE '^#include[[:space:]]+"[^"]+"' "src/$i" 2>/dev/null | sed -E 's/.*"(.*)"/\1/'); do deps="$deps src/$j"; done
  done
  echo "$objdir/$base.o:$deps"
done
