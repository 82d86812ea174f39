#!/usr/bin/env bash
# Benchmarks: set-up (packages incl. libsundials-dev, Release build), then flexmb_bench.
# Arguments are passed on: tools/bench.sh [--quick] [--out DIR]
# Output (default): validation/report/bench/{bench.md, *.csv, *.svg}. The full run takes ~6-10 min
# on 2 cores (it is single-threaded; other load on the machine inflates the wall times).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
BUILD_DIR=${FLEXMB_BUILD_DIR:-build}
cmake --build "$BUILD_DIR" --target flexmb_bench -j"$(nproc)"
"$BUILD_DIR/flexmb_bench" "$@"
