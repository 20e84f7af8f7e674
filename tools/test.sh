#!/usr/bin/env bash
# Installs, builds and runs every test (GoogleTest through CTest), on all cores.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 600
