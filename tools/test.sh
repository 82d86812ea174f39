#!/usr/bin/env bash
# The whole test suite: set-up (packages, Release build), then ctest. CI runs it: the project's own
# code builds with -Werror (FLEXMB_WERROR: a warning in flexmb's code fails the build).
set -euo pipefail
cd "$(dirname "$0")/.."
FLEXMB_CMAKE_ARGS="-DFLEXMB_WERROR=ON ${FLEXMB_CMAKE_ARGS:-}" bash tools/setup.sh
# The public SPACAR Light script that octave_test_spacarlight runs unchanged (needs network; without
# it that one test reports itself skipped).
timeout 120 sh tools/octave/fetch_public_scripts.sh 2>/dev/null ||
  echo "tools/octave/fetch_public_scripts.sh: no copy of SPACAR Light (no network?); octave_test_spacarlight will be skipped"
ctest --test-dir "${FLEXMB_BUILD_DIR:-build}" --output-on-failure -j"$(nproc)"
