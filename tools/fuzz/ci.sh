#!/usr/bin/env bash
# Short fuzzing run for CI: builds the libFuzzer target with clang (ASan + UBSan) in $1 (default
# build/fuzz) and runs it on the shipped models as seed corpus for FLEXMB_FUZZ_RUNS inputs
# (default 20000) or FLEXMB_FUZZ_SECONDS (default 120), whichever comes first. Exit 77 (ctest: skipped)
# only when clang++ or libFuzzer is not installed. Does not take the CPU lock itself: run the
# test suite under it (GUIDE/README).
set -euo pipefail
src="$(cd "$(dirname "$0")/../.." && pwd)"
dir="${1:-$src/build/fuzz}"
cxx="$(command -v clang++ || command -v clang++-14 || true)"
if [ -z "$cxx" ]; then
  echo "SKIPPED: clang++ is not installed (Debian: apt-get install clang libclang-rt-14-dev; tools/setup.sh does it)"
  exit 77
fi
if ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long){return 0;}' |
     "$cxx" -x c++ -fsanitize=fuzzer - -o /dev/null 2>/dev/null; then
  echo "SKIPPED: $cxx cannot link libFuzzer (Debian: apt-get install libclang-rt-14-dev; tools/setup.sh does it)"
  exit 77
fi
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$src" -B "$dir" -DCMAKE_CXX_COMPILER="$cxx" -DFLEXMB_FUZZ=ON -DBUILD_TESTING=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" >/dev/null
cmake --build "$dir" -j2 --target flexmb_fuzz_dat >/dev/null
corpus="$(mktemp -d)"
trap 'rm -rf "$corpus"' EXIT
seeds=("$src"/datfiles "$src"/datfiles/tests "$src"/io/tests/data)
echo "fuzzing the .dat reader + model builder + kinematic check with seeds from ${seeds[*]}"
"$dir/flexmb_fuzz_dat" -runs="${FLEXMB_FUZZ_RUNS:-20000}" -max_total_time="${FLEXMB_FUZZ_SECONDS:-120}" \
  -max_len=8192 -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 \
  -artifact_prefix="$dir/" "$corpus" "${seeds[@]}"
