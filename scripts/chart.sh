#!/usr/bin/env bash
# Speed against accuracy: runs bumprad-bench-accuracy (about 15 minutes on 2 cores) and
# draws docs/speed-accuracy.png from docs/speed-accuracy.csv with gnuplot.
#   scripts/chart.sh            sweep, then draw
#   scripts/chart.sh --draw     draw the CSV already in docs/
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v gnuplot >/dev/null; then
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends gnuplot-nox
fi
if [[ "${1:-}" != "--draw" ]]; then
  scripts/setup.sh
  build/bin/bumprad-bench-accuracy point perturbed cornell wrinkled-box paper-room \
    > docs/speed-accuracy.csv.tmp
  mv docs/speed-accuracy.csv.tmp docs/speed-accuracy.csv
fi
gnuplot scripts/speed-accuracy.gp
echo "wrote docs/speed-accuracy.png from docs/speed-accuracy.csv"
