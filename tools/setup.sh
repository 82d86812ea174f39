#!/usr/bin/env bash
# Installs the Debian packages flexmb needs (skipping what is installed), then configures and
# builds a Release build in ./build (FLEXMB_BUILD_DIR): every target, or only the targets named as
# arguments (tools/run.sh builds flexmb and flexmb_bench). Idempotent: safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake make pkg-config libeigen3-dev libsuitesparse-dev libarpack2-dev
          libboost-program-options-dev libgtest-dev libmuparser-dev libmatio-dev python3-scipy libsundials-dev)
# A full build (no target named: the test suite) also needs: octave + liboctave-dev for the
# Octave/MATLAB gateway (tools/octave) and its tests, octave-control for getss's ss object, gnuplot-nox and
# fonts-freefont-otf (Octave's default font) so that octave-cli makes figures without a display (spadraw's
# test draws into one); calculix-ccx, the independent FE oracle of the
# spatial tests; clang + libclang-rt-14-dev (libFuzzer, sanitizer runtimes) for tools/fuzz; chromium
# for the headless browser test of the HTML animation; pybind11-dev, python3-dev and python3-pytest for
# the Python module (tools/python) and its tests, python3-matplotlib for its example; strace for the
# test that every front end opens the .dat once (tools/tests/check_one_read.py); mkdocs and
# mkdocs-material for the documentation site (tools/docs.sh, ctest docs_site). The main job (named
# targets) skips them.
(($#)) || packages+=(octave liboctave-dev octave-control gnuplot-nox fonts-freefont-otf calculix-ccx clang libclang-rt-14-dev chromium
                     pybind11-dev python3-dev python3-pytest python3-matplotlib strace mkdocs mkdocs-material)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

BUILD_DIR=${FLEXMB_BUILD_DIR:-build}
# FLEXMB_CMAKE_ARGS: extra configure options (tools/test.sh: -DFLEXMB_WERROR=ON). They stay in the
# build's cache, so a later set-up without them does not rebuild everything.
# shellcheck disable=SC2086
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release ${FLEXMB_CMAKE_ARGS:-} >/dev/null
if (($#)); then
  cmake --build "$BUILD_DIR" -j"$(nproc)" --target "$@"
else
  cmake --build "$BUILD_DIR" -j"$(nproc)"
fi
