#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer, build and tests in one
# command (g++ by default; CXX=clang++ for clang). Configures build-sanitize/ (or $FLEXMB_SANITIZE_DIR)
# with -DFLEXMB_SANITIZE=ON (-O1 -g1, unity batches, no benchmark program: CMakeLists.txt), builds
# what the suite runs and runs ctest there; any sanitizer report fails the test that triggered it
# (-fno-sanitize-recover, halt_on_error). Left out: the `fuzz` tests (they build their own sanitized
# clang tree), the `benchmark` tests (timings, meaningless here) and `format` (no compiled code);
# the `slow` tests run their short versions. Extra arguments go to ctest (e.g. -R Sparse or -L io).
# Prints the build and test times (tools/README.md has the measured figures).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${FLEXMB_SANITIZE_DIR:-build-sanitize}

generator=()
[ ! -f "$dir/CMakeCache.txt" ] && command -v ninja >/dev/null && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFLEXMB_SANITIZE=ON \
  ${CXX:+-DCMAKE_CXX_COMPILER=$CXX} "${launcher[@]}" >/dev/null

t0=$(date +%s)
cmake --build "$dir" -j"$(nproc)"
t1=$(date +%s)
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
rc=0
ctest --test-dir "$dir" -j"$(nproc)" --output-on-failure -LE 'fuzz|benchmark|format' "$@" || rc=$?
t2=$(date +%s)
echo "sanitize: build $((t1 - t0)) s, tests $((t2 - t1)) s, total $((t2 - t0)) s (ctest exit $rc)"
exit $rc
