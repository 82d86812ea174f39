#!/usr/bin/env bash
# Figures of `flexmb study` (tools/study/README.md), to run alone on the machine (nothing else busy):
#   1. speed-up of --jobs 2 over --jobs 1: 100 variants of the cross-spring pivot template (leaf
#      thickness from 0.1 to 0.5 mm), static analysis with 10 load steps and 6 frequencies in each;
#   2. the study's cost per variant beyond its analysis, from the same --jobs 1 runs: (wall time -
#      the analyses' own time, which each worker measures around analysis::runVariant and writes in
#      its manifest) / 100. Everything else counts as overhead: the fork, the template, writing and
#      reading the model, the variant's files and manifest, the collected table, report and plots;
#   3. for scale: the same 100 instantiated models through 100 `flexmb static` calls (the shell
#      loop a study replaces).
#   bash tools/study/bench_study.sh [flexmb binary] [repeats]
set -euo pipefail
flexmb=$(readlink -f "${1:-build/flexmb}")
repeats=${2:-3}
src=$(cd "$(dirname "$0")/../.." && pwd)
template="$src/datfiles/spatial/cross_spring_pivot_study.dat"
work=$(mktemp -d /tmp/flexmb_study_bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"
now() { date +%s%N; }
ms() { echo $((($2 - $1) / 1000000)); }

analysisMs() { awk -F': ' '/^analysis seconds: / { s += $2 } END { printf "%.1f", s * 1000 }' "$1"/variants/*/*_run.txt; }

echo "flexmb study benchmark ($(nproc) cores, $(date -u +%Y-%m-%d))"
best1=0 best2=0 bestOver=
for r in $(seq "$repeats"); do
  for jobs in 1 2; do
    rm -rf "s$jobs"
    t0=$(now)
    "$flexmb" study "$template" --param t=0.1e-3:0.5e-3:100 --static --steps 10 --nev 6 --jobs "$jobs" \
      --out "s$jobs" -q
    t=$(ms "$t0" "$(now)")
    a=$(analysisMs "s$jobs")
    echo "  run $r, --jobs $jobs: 100 variants in $t ms (the analyses' own time: $a ms in all)"
    if [ "$jobs" = 1 ]; then
      { [ "$best1" = 0 ] || [ "$t" -lt "$best1" ]; } && best1=$t
      over=$(awk -v w="$t" -v a="$a" 'BEGIN { printf "%.2f", (w - a) / 100 }')
      { [ -z "$bestOver" ] || awk -v o="$over" -v b="$bestOver" 'BEGIN { exit !(o < b) }'; } && bestOver=$over
    fi
    if [ "$jobs" = 2 ]; then { [ "$best2" = 0 ] || [ "$t" -lt "$best2" ]; } && best2=$t; fi
  done
  cmp -s s1/study_summary.csv s2/study_summary.csv || { echo "tables differ"; exit 1; }
done
speedup=$(awk -v a="$best1" -v b="$best2" 'BEGIN { printf "%.2f", a / b }')
echo "speed-up --jobs 2 over --jobs 1 (best of $repeats): $best1 ms / $best2 ms = ${speedup}x"
echo "overhead per variant beyond its analysis (--jobs 1: (wall - analyses) / 100, best of $repeats): $bestOver ms"

t0=$(now)
for f in s1/variants/*/cross_spring_pivot_study.dat; do
  "$flexmb" static "$f" --steps 10 --nev 6 --out "$work/single.csv" -q >/dev/null
done
t=$(ms "$t0" "$(now)")
echo "  for scale, the same 100 models through 100 \`flexmb static\` calls: $t ms" \
  "($(awk -v w="$t" 'BEGIN { printf "%.1f", w / 100 }') ms each)"
