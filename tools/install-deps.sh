#!/usr/bin/env bash
# Installs every Debian package clothsim needs to build, test and make its figures.
# This is the one list of the project's dependencies; CMakeLists.txt finds what it installs.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev            # flat state, sparse Jacobians, conjugate gradient
  libyaml-cpp-dev          # scene files
  libhwy-dev               # Google Highway: the SIMD spring force kernel, one binary for x86-64 up to AVX-512
  libcli11-dev             # command line
  libosmesa6-dev           # offscreen OpenGL through OSMesa (llvmpipe), no GPU or display
  libegl-dev libegl-mesa0 libgl-dev  # offscreen OpenGL through EGL (surfaceless on Mesa, device on NVIDIA)
  libpng-dev zlib1g-dev    # frames and golden images
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev   # MP4 through FFmpeg's libraries
  libgtest-dev libbenchmark-dev   # tests and benchmarks
  libbullet-dev            # a peer in benchmarks only (tools/bench/bullet_peer_bench.cpp)
  libsuitesparse-dev libopenblas0-pthread  # CHOLMOD on OpenBLAS, a peer in benchmarks only (cholmod_peer_bench.cpp)
  libhypre-dev             # hypre's BoomerAMG (pulls in OpenMPI), a peer in benchmarks only (hypre_implicit_bench.cpp)
  python3-matplotlib       # tools/plot_*.py figures (run with /usr/bin/python3)
  pybind11-dev python3-dev python3-numpy   # the clothsim Python module (tools/python), for /usr/bin/python3
  python3-pytest python3-pandas python3-pil  # its tests (tests/python), run by tools/test.sh
  python3-meshio           # exported meshes read back (tests/export: PLY, OBJ)
  jupyter-nbconvert python3-ipykernel   # docs/notebooks/report.ipynb, executed by ctest (Notebook.*)
  time                     # GNU time, for tools/benchmarks.sh
  clang-14 libclang-rt-14-dev   # the libFuzzer target (tools/fuzz.sh): -fsanitize=fuzzer,address,undefined
)
# The clients mesh export is for, run headless by tests/export/clients_test.sh: about 1.1 GB
# installed with their ~200 dependencies (Qt 5, VTK, OpenMPI), blender 85 MB and paraview 430 MB
# of it. CLOTHSIM_NO_CLIENTS=1 leaves them out (their three tests then say "skipped").
clients=(
  blender                  # Blender 3.4 (-b --python): OBJ import, the Mesh Cache modifier on PC2
  paraview python3-paraview  # ParaView 5.11's pvpython: the .pvd collection
)

[[ ${CLOTHSIM_NO_CLIENTS:-0} == 1 ]] || packages+=("${clients[@]}")

if [[ $(id -u) -ne 0 ]]; then sudo=sudo; else sudo=; fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
