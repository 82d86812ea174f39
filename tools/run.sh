#!/usr/bin/env bash
# The main job: set-up, then the paper validation (for now the kinematic check of the paper's
# models; the full report comes with `flexmb validate`).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
for f in datfiles/straight_guidance.dat datfiles/manipulator.dat datfiles/slider_crank_s95.dat; do
  echo "== flexmb check $f"
  ./build/flexmb check "$f"
done
