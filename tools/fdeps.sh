#!/usr/bin/env bash
# Writes make dependencies for Fortran sources: one module per file, named
# after the module, so "use X" in a file means its object needs X.o.
# Usage: [GENDIR=build/gen] tools/fdeps.sh OBJDIR file...   (prints rules on stdout)
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
  # included files, to any depth; one that is not in src/ is generated into build/gen/ from a
  # src/*.fypp list (Makefile), and the files those lists include count as well
  todo=$(grep -oE '^#include[[:space:]]+"[^"]+"' "$f" | sed -E 's/.*"(.*)"/\1/' || true)
  seen=" "
  while [ -n "$todo" ]; do
    next=""
    for i in $todo; do
      case "$seen" in *" $i "*) continue ;; esac
      seen="$seen$i "
      if [ -e "src/$i" ]; then
        deps="$deps src/$i"
        src="src/$i"
      else
        deps="$deps ${GENDIR:-build/gen}/$i"
        src=$(ls src/*.fypp 2>/dev/null || true)
      fi
      [ -n "$src" ] || continue
      next="$next $(grep -ohE '^#include[[:space:]]+"[^"]+"' $src | sed -E 's/.*"(.*)"/\1/' || true)"
    done
    todo=$next
  done
  echo "$objdir/$base.o:$deps"
done
