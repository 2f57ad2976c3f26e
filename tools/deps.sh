#!/usr/bin/env bash
# Install everything MBSPH needs to build, test, lint and post-process (called by `make deps`).
# Idempotent: installs only what is missing; when all is there it takes about a second.
#
#   (a) Debian packages: Fortran/MPI/HDF5/FFTW toolchain, and ParaView + Xvfb for the
#       ParaView test (skip those with MBSPH_NO_PARAVIEW=1).
#   (b) Python virtual environment .venv/ in the repository root with the exact versions
#       of tools/requirements.txt and the post package (pyproject.toml) installed editable;
#       rebuilt only when requirements.txt or pyproject.toml is newer than the stamp
#       .venv/.deps-stamp (or the environment is missing or broken).
#
# Environment: MBSPH_NO_PARAVIEW=1  skip paraview/xvfb
#              MBSPH_PYTHON=...     interpreter to build .venv from (default: python3 on PATH)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

say() { printf 'deps: %s\n' "$*"; }

# ---------------------------------------------------------------- (a) Debian packages
# time: GNU time, which measures the peak memory of the runs of post/study.py
pkgs=(gfortran libopenmpi-dev openmpi-bin libhdf5-openmpi-dev libfftw3-dev make time)
if [[ "${MBSPH_NO_PARAVIEW:-0}" != 1 ]]; then
    # pvpython is in paraview; its Python modules in python3-paraview; xvfb-run needs xauth
    pkgs+=(paraview python3-paraview xvfb xauth)
fi

python=${MBSPH_PYTHON:-python3}
if ! command -v "$python" >/dev/null 2>&1; then
    pkgs+=(python3 python3-venv)
    python=python3
elif ! "$python" -c 'import venv, ensurepip' >/dev/null 2>&1; then
    # Debian's own /usr/bin/python3 needs python3-venv for `python3 -m venv` (pyenv's has it built in)
    pkgs+=(python3-venv)
fi

missing=()
for p in "${pkgs[@]}"; do
    status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
    [[ "$status" == installed ]] || missing+=("$p")
done

if ((${#missing[@]})); then
    say "installing Debian packages: ${missing[*]}"
    sudo=()
    if [[ $(id -u) != 0 ]]; then sudo=(sudo); fi
    apt_opts=(-y -qq -o Dpkg::Use-Pty=0 -o DPkg::Lock::Timeout=600 --no-install-recommends)
    log=$(mktemp)
    t0=$SECONDS
    # apt's chatter goes to a log that is shown only when something fails
    if ! { "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
           "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install "${apt_opts[@]}" \
               "${missing[@]}"; } >"$log" 2>&1; then
        cat "$log" >&2
        say "apt-get failed" >&2
        exit 1
    fi
    rm -f "$log"
    say "Debian packages installed in $((SECONDS - t0)) s"
fi

# ---------------------------------------------------------------- (b) Python venv
venv=$root/.venv
req=$root/tools/requirements.txt
stamp=$venv/.deps-stamp

if [[ -f "$stamp" && ! "$req" -nt "$stamp" && ! "$root/pyproject.toml" -nt "$stamp" ]] &&
   "$venv/bin/python" -c '' >/dev/null 2>&1; then
    exit 0
fi

t0=$SECONDS
if ! "$venv/bin/python" -c 'import pip' >/dev/null 2>&1; then
    say "creating $venv with $("$python" --version 2>&1)"
    rm -rf "$venv"
    "$python" -m venv "$venv"
fi
say "installing Python packages from tools/requirements.txt"
export PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_NO_INPUT=1
"$venv/bin/python" -m pip install -q --only-binary=h5py,numpy,scipy -r "$req"
# the post package itself (pyproject.toml), editable: `import post` from any folder, `mbsph-post`
"$venv/bin/python" -m pip install -q --no-deps --no-build-isolation -e "$root"
# fail here, not in a test, if a wheel does not load
"$venv/bin/python" -c 'import numpy, scipy.signal, scipy.spatial, h5py, matplotlib, f90nml, pytest, post' >/dev/null
"$venv/bin/mbsph-post" --help >/dev/null
"$venv/bin/fortitude" --version >/dev/null
"$venv/bin/fypp" --version >/dev/null
touch "$stamp"
say "Python environment ready in $((SECONDS - t0)) s"
