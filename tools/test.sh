#!/usr/bin/env bash
# The whole test suite: set-up (packages, Release build), then ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
ctest --test-dir "${FLEXMB_BUILD_DIR:-build}" --output-on-failure -j"$(nproc)"
