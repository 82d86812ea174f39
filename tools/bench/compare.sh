#!/usr/bin/env bash
# The benchmark of another commit and of this tree, in one run: builds flexmb_bench at REV in a
# temporary worktree, then runs both alternately (ROUNDS times each, default 2) with --quick
# --only ONLY (default rhs: the right-hand-side cost over the mesh) and prints one table with both
# medians and their ratio (best of the rounds). For "the RHS cost within noise of before".
#   bash tools/bench/compare.sh eca61e6^ [rhs] [rounds]
set -euo pipefail
cd "$(dirname "$0")/../.."
rev=${1:?usage: tools/bench/compare.sh REV [ONLY] [ROUNDS]}
only=${2:-rhs}
rounds=${3:-2}
work=$(mktemp -d)
trap 'git worktree remove --force "$work/base" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
git worktree add --detach "$work/base" "$rev" >/dev/null
echo "compare: building flexmb_bench at $(git -C "$work/base" log --oneline -1)"
cmake -S "$work/base" -B "$work/base/build" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF >/dev/null
cmake --build "$work/base/build" -j"$(nproc)" --target flexmb_bench >/dev/null
bash tools/setup.sh flexmb_bench >/dev/null
for r in $(seq "$rounds"); do
  "$work/base/build/flexmb_bench" --quick --only "$only" --out "$work/before$r" >/dev/null
  build/flexmb_bench --quick --only "$only" --out "$work/after$r" >/dev/null
done
python3 - "$work" "$rounds" "$rev" <<'PY'
import csv, sys
work, rounds, rev = sys.argv[1], int(sys.argv[2]), sys.argv[3]
def load(p):
    return {int(r["elements_per_flexure"]): float(r["median_rhs_s"]) for r in csv.DictReader(open(p))}
b = [load(f"{work}/before{r}/rhs_scaling.csv") for r in range(1, rounds + 1)]
a = [load(f"{work}/after{r}/rhs_scaling.csv") for r in range(1, rounds + 1)]
print(f"| elements per flexure | {rev} [us] | this tree [us] | this tree / {rev} (best of {rounds}) |")
print("|---|---|---|---|")
for k in sorted(b[0]):
    bb, aa = min(x[k] for x in b), min(x[k] for x in a)
    print(f"| {k} | {' / '.join(f'{x[k]*1e6:.2f}' for x in b)} | {' / '.join(f'{x[k]*1e6:.2f}' for x in a)} | {aa/bb:.3f} |")
PY
