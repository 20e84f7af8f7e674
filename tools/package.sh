#!/usr/bin/env bash
# Builds the product (tools/build.sh) and packs it as a .deb with CPack (tools/package):
# build/clothsim_VERSION_ARCH.deb, installable with `apt install ./build/clothsim_*.deb`.
# Usage: tools/package.sh [extra cmake -D options...]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh "$@"
(cd build && cpack -G DEB >/dev/null)
deb=$(ls -t build/clothsim_*.deb | head -1)
echo "package: $deb (apt install ./$deb)" >&2
