#!/usr/bin/env bash
# The main job: set-up (packages; a Release build of flexmb and the benchmark only), then a quick
# run-time-against-error benchmark (validation/report/bench/, with the guidance's process time
# against its error to the converged continuum: guidance_continuum.md; the full model against basis
# auto in one run: single_run_economics.md) and the paper validation into
# validation/report/ (report.md with figures and CSV). About 7 minutes on 2 cores from a fresh
# clone on a quiet machine, most of it the build; it prints its plan with estimates at the start
# and what remains after each phase.
#   --full   also the slow numerical stress catalogue (validation/report/stress.csv, ~17 min) and the
#            full benchmark with tight-tolerance references (~14 min) instead of the quick one.
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
BUILD_DIR=${FLEXMB_BUILD_DIR:-build}
cores=$(nproc)

# ---- the plan: phases with estimates (seconds on a quiet machine with $cores cores)
# Build: about 21 CPU-seconds per translation unit still to compile, a unit being a unity batch of
# up to 8 files (measured 2026-12-06: a cold unity build of flexmb and flexmb_bench, 26 units, 4 min
# 50 s on 2 cores with the set-up); the count comes from a dry run of make when the build folder is
# configured, else every unit of the two targets.
compile_units=26
((full)) && compile_units=$((compile_units + 2))
if [ -f "$BUILD_DIR/Makefile" ]; then
  pending=$(make -C "$BUILD_DIR" -n "${targets[@]}" 2>/dev/null | grep -c 'Building CXX object' || true)
  compile_units=${pending:-$compile_units}
fi
est_build=$(((compile_units * 21 + cores - 1) / cores + 5))
if ((full)); then
  est_stress=1020; est_bench=830  # +230 s since 2026-12-06: the 20-element guidance (its galpha reference at 1e-8: 70 s)
else
  # quick benchmark: 113-118 s as a process (2026-12-06; eigen and operator sections ~24 s, then
  # 89-92 s of work-precision, elbow and rhs scaling)
  est_stress=0; est_bench=115
fi
est_bench=$((est_bench + 6))  # the guidance against its converged answer: 5.7 s (2026-12-07)
est_bench=$((est_bench + 19))  # single-run economics, issue 49 item 6: 18.9 s (2026-12-07)
est_report=30  # flexmb validate: 29 s measured with the reduction error tables (2026-11-28)

duration() {  # seconds -> "4 min 10 s", "45 s"
  local s=$1
  if ((s >= 60)); then echo "$((s / 60)) min $((s % 60)) s"; else echo "${s} s"; fi
}
remaining() {  # the phases still to come, from the index given
  local from=$1 text="" total=0 i
  local names=("building" "stress tests" "benchmark" "report")
  local secs=("$est_build" "$est_stress" "$est_bench" "$est_report")
  for ((i = from; i < 4; i++)); do
    ((secs[i] == 0)) && continue
    text+="${text:+, }${names[i]} (about $(duration "${secs[i]}"))"
    total=$((total + secs[i]))
  done
  echo "$text: about $(duration $total) in all"
}
load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo 0)
busy=""
if awk -v l="$load" -v c="$cores" 'BEGIN { exit !(l > c) }'; then
  busy=" (the machine is busy, load average $load on $cores cores: expect it to take longer)"
fi
echo "== plan: $(remaining 0)$busy"
[ -n "${FLEXMB_RUN_PLAN_ONLY:-}" ] && exit 0  # the plan alone (tools/tests: Scripts.RunPrintsItsPlan)
phase_start=$SECONDS
done_phase() {  # phase name, index of the next phase
  local took=$((SECONDS - phase_start))
  if (($2 < 4)); then
    echo "== $1 done in $(duration $took); remaining: $(remaining "$2")"
  else
    echo "== $1 done in $(duration $took); all done in $(duration $SECONDS)"
  fi
  phase_start=$SECONDS
}

# Unity batches (CMakeLists.txt): flexmb and the benchmark compile in about half the time (7 min 20 s
# file by file on 2 cores).
FLEXMB_CMAKE_ARGS="-DCMAKE_UNITY_BUILD=ON ${FLEXMB_CMAKE_ARGS:-}" bash tools/setup.sh "${targets[@]}"
mkdir -p validation/report
done_phase "build" $((full ? 1 : 2))

if ((full)); then
  echo "== numerical stress tests (all cases, including the slow ones)"
  FLEXMB_SLOW_STRESS=1 FLEXMB_STRESS_CSV=validation/report/stress.csv \
    "$BUILD_DIR/validation/stress_tests" --gtest_brief=1 || echo "stress tests: failures above (see the report)"
  done_phase "stress tests" 2
  echo "== run time against error (full)"
  "$BUILD_DIR/flexmb_bench" --out validation/report/bench
else
  echo "== run time against error (quick; bash tools/run.sh --full for the full benchmark and the stress catalogue)"
  "$BUILD_DIR/flexmb_bench" --quick --out validation/report/bench
fi
echo "== the guidance against its converged continuum answer (issue 50: process time against true error)"
python3 tools/bench/guidance_continuum.py --flexmb "$BUILD_DIR/flexmb" \
  --out validation/report/bench/guidance_continuum.md || echo "guidance against its converged answer: failed (above)"
echo "== single-run economics: the full model against basis auto (issue 49: process time against the error to the full model)"
python3 tools/bench/single_run_economics.py --flexmb "$BUILD_DIR/flexmb" \
  --out validation/report/bench/single_run_economics.md || echo "single-run economics: failed (above)"
done_phase "benchmark" 3

echo "== paper validation"
"$BUILD_DIR/flexmb" validate
done_phase "report" 4
echo "report: validation/report/report.md"
