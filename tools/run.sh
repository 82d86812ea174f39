#!/usr/bin/env bash
# The main job: set-up (packages; a Release build of flexmb and the benchmark only), then the paper
# validation into validation/report/ (report.md with figures and CSV) and a quick run-time-against-
# error benchmark (validation/report/bench/). Under 10 minutes on 2 cores from a fresh clone.
#   --full   also the slow numerical stress catalogue (validation/report/stress.csv, ~17 min) and the
#            full benchmark with tight-tolerance references (~10 min) instead of the quick one.
set -euo pipefail
cd "$(dirname "$0")/.."
full=0
for a in "$@"; do
  case "$a" in
    --full) full=1 ;;
    *) echo "usage: bash tools/run.sh [--full]" >&2; exit 2 ;;
  esac
done
targets=(flexmb flexmb_bench)
((full)) && targets+=(stress_tests)
bash tools/setup.sh "${targets[@]}"
BUILD_DIR=${FLEXMB_BUILD_DIR:-build}
mkdir -p validation/report

if ((full)); then
  echo "== numerical stress tests (all cases, including the slow ones)"
  FLEXMB_SLOW_STRESS=1 FLEXMB_STRESS_CSV=validation/report/stress.csv \
    "$BUILD_DIR/validation/stress_tests" --gtest_brief=1 || echo "stress tests: failures above (see the report)"
  echo "== run time against error (full)"
  "$BUILD_DIR/flexmb_bench" --out validation/report/bench
else
  echo "== run time against error (quick; bash tools/run.sh --full for the full benchmark and the stress catalogue)"
  "$BUILD_DIR/flexmb_bench" --quick --out validation/report/bench
fi

echo "== paper validation"
"$BUILD_DIR/flexmb" validate
echo "report: validation/report/report.md"
