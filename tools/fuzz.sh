#!/usr/bin/env bash
# Builds the scene front end's libFuzzer target with clang-14 (ASan + UBSan) in build-fuzz/
# and fuzzes it for SECONDS (default 60), seeded with scenes/ and tests/fuzz/regressions/,
# with the dictionary tests/fuzz/scene.dict.
# New coverage goes to CLOTHSIM_FUZZ_CORPUS (default build-fuzz/corpus, kept between runs); a
# failing input is written to
# build-fuzz/crash-* (copy it into tests/fuzz/regressions/ with the fix, so the ordinary
# suite checks it from then on). Extra arguments go to libFuzzer (-jobs=2, -max_len=...).
# Usage: tools/fuzz.sh [SECONDS] [libFuzzer options...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
cxx=${CLOTHSIM_FUZZ_CXX:-clang++-14}
if ! command -v "$cxx" >/dev/null; then
  echo "fuzz: $cxx not found (Debian: apt-get install clang-14 libclang-rt-14-dev)" >&2
  exit 2
fi
cmake -S tools/fuzz -B build-fuzz -DCMAKE_CXX_COMPILER="$cxx" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target scene_fuzzer >/dev/null
corpus=${CLOTHSIM_FUZZ_CORPUS:-build-fuzz/corpus}
mkdir -p "$corpus"
echo "fuzz: scene_fuzzer for ${seconds} s (ASan + UBSan), corpus $corpus" >&2
# -max_len: room for every seed (the shipped scenes are under 2 kB) and for mutations that
# grow them; -rss_limit_mb and -malloc_limit_mb: a run past them is a leak or an unbounded
# allocation, a failure (with the allocation's stack for the latter).
exec build-fuzz/scene_fuzzer -max_total_time="$seconds" -max_len=8192 -rss_limit_mb=2048 -malloc_limit_mb=512 -timeout=10 \
  -dict=tests/fuzz/scene.dict -artifact_prefix=build-fuzz/ -print_final_stats=1 "$@" \
  "$corpus" scenes tests/fuzz/regressions
