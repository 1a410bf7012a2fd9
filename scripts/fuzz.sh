#!/usr/bin/env bash
# Fuzzes the request and scene parsers (tests/fuzz/request_fuzz.cpp) with libFuzzer,
# AddressSanitizer and UBSan, built with clang into build-fuzz/:
#   scripts/fuzz.sh --build-only       build only (scripts/setup.sh --tests does this)
#   scripts/fuzz.sh --seconds 30       fuzz for 30 s (the test suite's short run)
#   scripts/fuzz.sh --runs 5000000     fuzz for 5 million inputs (the long run, a benchmark)
# The corpus grows in build-fuzz/corpus from the seeds in tests/fuzz/corpus; a crashing
# input is written to build-fuzz/findings/ and the script exits non-zero.
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:---seconds}
amount=${2:-600}
case "$mode" in
  --build-only | --seconds | --runs) ;;
  *) echo "usage: scripts/fuzz.sh [--build-only | --seconds S | --runs N]" >&2; exit 2 ;;
esac

cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DBUMPRAD_FUZZ=ON >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target bumprad-fuzz-requests
[[ "$mode" == --build-only ]] && exit 0

mkdir -p build-fuzz/corpus build-fuzz/findings
limit=(-max_total_time="$amount")
[[ "$mode" == --runs ]] && limit=(-runs="$amount")
exec build-fuzz/bin/bumprad-fuzz-requests "${limit[@]}" -max_len=65536 -timeout=10 \
  -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix=build-fuzz/findings/ \
  build-fuzz/corpus tests/fuzz/corpus
