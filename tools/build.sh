#!/usr/bin/env bash
# Installs clothsim's Debian packages (if missing), configures and builds it in build/, the
# Python module in build/python/ included.
# Usage: tools/build.sh [extra cmake -D options...]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$(nproc)"
echo "build: ok ($(pwd)/build/clothsim)" >&2
# The Python module (tools/python), when pybind11 was found: docs/python.md.
[[ -d build/python ]] && echo "build: Python module in build/python: PYTHONPATH=$(pwd)/build/python /usr/bin/python3" >&2
exit 0
