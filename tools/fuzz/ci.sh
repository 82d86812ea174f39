#!/usr/bin/env bash
# CI's sanitizer and fuzz runs on one sanitized clang tree (ctest registers each step as a test,
# tools/fuzz/CMakeLists.txt; README.md in this folder):
#   ci.sh build DIR          configures DIR (clang, -DFLEXMB_FUZZ=ON: ASan + UBSan + libFuzzer coverage,
#                            -O1 -g1, unity batches) and builds the fuzz targets and the tests of core,
#                            solvers and io
#   ci.sh tests DIR [args]   runs those tests there (labels core, solvers, io and their -slow, which run
#                            their short versions; args go to ctest)
#   ci.sh fuzz DIR dat|basis fuzzes the .dat reader or the basis-file reader from the seeds below for
#                            FLEXMB_FUZZ_RUNS inputs (default 20000; -1: no limit) or FLEXMB_FUZZ_SECONDS
#                            (default 120), whichever comes first; new inputs go to FLEXMB_FUZZ_CORPUS
#                            (default: a temporary folder)
#   ci.sh seeds dat|basis OUT  only copies the seeds into OUT and prints the -max_len they need
# Seeds: every tracked *.dat model of the repository once (datfiles, the reader's SPACAR95 and SPACAR
# Light shapes in io/tests/data, tools/tests/data, the gateway's USERSIG models), and the basis files
# in tools/fuzz/seeds/basis. -max_len is the largest seed rounded up to 4 KiB (at least 8 KiB), so
# no shipped model is cut. Exit 77 (ctest: skipped) only when clang++ or libFuzzer is not installed.
set -euo pipefail
src="$(cd "$(dirname "$0")/../.." && pwd)"
cmd=${1:?usage: ci.sh build|tests|fuzz|seeds ...}
shift

need_clang() {
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
}

# seeds KIND OUT: copies the seeds into OUT (each content once) and prints the -max_len they need.
seeds() {
  local kind=$1 out=$2 f h largest=0 size
  local -A seen=()
  local files=()
  if [ "$kind" = dat ]; then
    if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
      mapfile -t files < <(git -C "$src" ls-files '*.dat' | sed "s|^|$src/|")
    else
      mapfile -t files < <(cd "$src" && find . -name '*.dat' -not -path './build*' | sed "s|^\.|$src|")
    fi
  else
    files=("$src"/tools/fuzz/seeds/basis/*)
  fi
  mkdir -p "$out"
  for f in "${files[@]}"; do
    [ -f "$f" ] || continue
    h=$(sha1sum <"$f" | cut -c1-40)
    [ -n "${seen[$h]:-}" ] && continue
    seen[$h]=1
    cp "$f" "$out/$(echo "${f#"$src"/}" | tr / _)"
    size=$(stat -c %s "$f")
    ((size > largest)) && largest=$size
  done
  local max=$(((largest + 4095) / 4096 * 4096))
  ((max < 8192)) && max=8192
  echo "$max"
}

case "$cmd" in
  build)
    need_clang
    dir=${1:?usage: ci.sh build DIR}
    launcher=()
    command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    generator=()
    [ ! -f "$dir/CMakeCache.txt" ] && command -v ninja >/dev/null && generator=(-G Ninja)
    cmake -S "$src" -B "$dir" "${generator[@]}" -DCMAKE_CXX_COMPILER="$cxx" -DFLEXMB_FUZZ=ON -DBUILD_TESTING=ON \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" >/dev/null
    t0=$(date +%s)
    cmake --build "$dir" -j"$(nproc)" --target flexmb_fuzz_dat flexmb_fuzz_basis core_tests solvers_tests io_tests
    echo "sanitized clang tree built in $(($(date +%s) - t0)) s"
    ;;
  tests)
    need_clang
    dir=${1:?usage: ci.sh tests DIR}
    shift
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
    ctest --test-dir "$dir" -j"$(nproc)" --output-on-failure -L '^(core|solvers|io)(-slow)?$' "$@"
    ;;
  fuzz)
    need_clang
    dir=${1:?usage: ci.sh fuzz DIR dat|basis}
    kind=${2:?usage: ci.sh fuzz DIR dat|basis}
    case "$kind" in dat | basis) ;; *) echo "ci.sh fuzz: unknown target '$kind' (dat or basis)" >&2; exit 2 ;; esac
    work="$(mktemp -d)"
    trap 'rm -rf "$work"' EXIT
    corpus=${FLEXMB_FUZZ_CORPUS:-$work/corpus}
    mkdir -p "$corpus"
    maxlen=$(seeds "$kind" "$work/seeds")
    echo "fuzzing the $kind reader: $(ls "$work/seeds" | wc -l) seeds ($(ls "$work/seeds" | tr '\n' ' ')), -max_len=$maxlen"
    "$dir/flexmb_fuzz_$kind" -runs="${FLEXMB_FUZZ_RUNS:-20000}" -max_total_time="${FLEXMB_FUZZ_SECONDS:-120}" \
      -max_len="$maxlen" -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 \
      -artifact_prefix="$dir/" "$corpus" "$work/seeds"
    ;;
  seeds)
    seeds "${1:?usage: ci.sh seeds dat|basis OUT}" "${2:?usage: ci.sh seeds dat|basis OUT}"
    ;;
  *)
    echo "usage: ci.sh build|tests|fuzz|seeds ..." >&2
    exit 2
    ;;
esac
