#!/usr/bin/env bash
# Shared set-up for run.sh and test.sh: install missing Debian packages (as root, via apt-get),
# then configure and build nhc (Release) in ./build.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config git
  libginac-dev libcln-dev ginac-tools
  libeigen3-dev libsundials-dev libsuitesparse-dev
  libfmt-dev catch2 libtomlplusplus-dev libcli11-dev
  texlive-latex-base clang
  gnuplot-nox
  libssl-dev
  coinor-libipopt-dev
  libhdf5-dev libopenmpi-dev openmpi-bin
  pybind11-dev python3-dev python3-numpy python3-pytest python3-scipy python3-sympy
  python3-nbclient python3-ipykernel python3-matplotlib python3-pil python3-h5py
  python3-scipy python3-sympy
  libjs-three chromium
  python3-sphinx python3-myst-parser python3-nbsphinx furo libjs-mathjax node-normalize.css pandoc mypy
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [ "$(id -u)" -ne 0 ]; then
    echo "setup: missing packages: ${missing[*]} (run as root to install them)" >&2
    exit 1
  fi
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Optional (now also required above, by the tutorial notebooks): bench/whipple_sympy.py uses it (SymPy's bicycle, timed against nhc linearize);
# the bench skips SymPy with a message without it, so a failed install is not an error.
optional=(python3-sympy)
for p in "${optional[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" && continue
  if [ "$(id -u)" -eq 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$p" >/dev/null 2>&1 ||
      echo "setup: optional $p not installed (bench/whipple_sympy.py will skip SymPy)" >&2
  fi
done

jobs=$(nproc 2>/dev/null || echo 2)
build_start=$SECONDS
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs"
echo "setup.sh: the build took $((SECONDS - build_start)) s" >&2
