#!/usr/bin/env bash
# Quick start: set up, then solve and render the built-in Cornell box to out/cornell.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p out
build/bin/bumprad render builtin:cornell -o out/cornell.png --export-solution out/cornell-solution.json
