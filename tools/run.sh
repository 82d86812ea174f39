#!/usr/bin/env bash
# The main job: set-up, then the paper validation into validation/report/ (report.md with figures
# and CSV), the run-time-against-error benchmark (validation/report/bench/) and the slow numerical
# stress cases (validation/report/stress.csv). Pass --quick for a shorter benchmark.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
mkdir -p validation/report
quick=""
[ "${1:-}" = "--quick" ] && quick="--quick"

echo "== numerical stress tests (all cases, including the slow ones)"
FLEXMB_SLOW_STRESS=1 FLEXMB_STRESS_CSV=validation/report/stress.csv \
  ./build/validation/stress_tests --gtest_brief=1 || echo "stress tests: failures above (see the report)"

echo "== run time against error"
if [ -x ./build/flexmb_bench ]; then
  ./build/flexmb_bench $quick --out validation/report/bench
fi

echo "== paper validation"
./build/flexmb validate
echo "report: validation/report/report.md"
