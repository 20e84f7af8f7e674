#!/usr/bin/env bash
# Installs clothsim's Debian packages (if missing), configures and builds it in build/.
# Usage: tools/build.sh [extra cmake -D options...]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$(nproc)"
echo "build: ok ($(pwd)/build/clothsim)" >&2
