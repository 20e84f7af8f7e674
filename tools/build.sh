#!/usr/bin/env bash
# Installs the product's Debian packages (if missing: tools/install-deps.sh product), then
# configures build/ and builds the product only: the clothsim CLI and the Python module in
# build/python. Tests and benchmarks are tools/test.sh's.
# Usage: tools/build.sh [extra cmake -D options...]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh product
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$(nproc)" --target clothsim_product
echo "build: ok ($(pwd)/build/clothsim)" >&2
# The Python module (tools/python), when pybind11 was found: docs/python.md.
[[ -d build/python ]] && echo "build: Python module in build/python: PYTHONPATH=$(pwd)/build/python /usr/bin/python3" >&2
exit 0
