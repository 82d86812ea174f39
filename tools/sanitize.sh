#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (g++ by default; set
# CXX=clang++ for clang): configures build-sanitize/ (or $FLEXMB_SANITIZE_DIR), builds everything and
# runs ctest there. Any sanitizer report fails the test that triggered it (-fno-sanitize-recover).
# Extra arguments go to ctest (e.g. -R io_ or -LE fuzz). Takes the CPU lock for build and tests when
# /tmp/flexmb-cpu.lock exists (the shared development machine); elsewhere it just runs.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${FLEXMB_SANITIZE_DIR:-build-sanitize}
lock=()
[ -e /tmp/flexmb-cpu.lock ] && lock=(flock /tmp/flexmb-cpu.lock)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFLEXMB_SANITIZE=ON ${CXX:+-DCMAKE_CXX_COMPILER=$CXX} \
  "${launcher[@]}" >/dev/null
"${lock[@]}" cmake --build "$dir" -j"$(nproc)"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The fuzz test builds its own clang tree; it is already sanitized, so it is left out here.
"${lock[@]}" ctest --test-dir "$dir" -j"$(nproc)" --output-on-failure -LE fuzz "$@"
