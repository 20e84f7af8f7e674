#!/usr/bin/env bash
# Installs clothsim's Debian packages: the one list of the project's dependencies, in two parts.
# CMakeLists.txt finds what it installs.
#   tools/install-deps.sh product   what the product needs to build and run: the CLI, the
#                                   Python module, the plots (tools/build.sh)
#   tools/install-deps.sh test      that and what the tests, benchmarks, fuzzer and their
#                                   peers and clients need (tools/test.sh); the default
set -euo pipefail

part=${1:-test}
case "$part" in
  product | test) ;;
  *) echo "install-deps: unknown part '$part' (product or test)" >&2; exit 2 ;;
esac

product=(
  build-essential cmake pkg-config
  libeigen3-dev            # flat state, sparse Jacobians, conjugate gradient
  libboost-dev             # Boost.Odeint: the adaptive reference (src/study/reference.cpp)
  libyaml-cpp-dev          # scene files
  libhwy-dev               # Google Highway: the SIMD spring force kernel, one binary for x86-64 up to AVX-512
  libcli11-dev             # command line
  libosmesa6-dev           # offscreen OpenGL through OSMesa (llvmpipe), no GPU or display
  libegl-dev libegl-mesa0 libgl-dev  # offscreen OpenGL through EGL (surfaceless on Mesa, device on NVIDIA)
  libpng-dev zlib1g-dev    # frames and golden images
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev   # MP4 through FFmpeg's libraries
  python3-matplotlib       # the --plot figures (tools/plot_*.py, run with /usr/bin/python3)
  pybind11-dev python3-dev python3-numpy python3-pandas   # the clothsim Python module (tools/python): arrays, DataFrames
  help2man                 # the man pages, read off the CLI's own --help (tools/package)
  file                     # CPack's .deb reads the programs' libraries with it (tools/package.sh)
)
tests=(
  libgtest-dev libbenchmark-dev   # tests and benchmarks
  valgrind                 # the memory-checked tier (tests/memcheck)
  libbullet-dev            # a peer in benchmarks only (tools/bench/bullet_peer_bench.cpp)
  libsuitesparse-dev libopenblas0-pthread  # CHOLMOD on OpenBLAS, a peer in benchmarks only (cholmod_peer_bench.cpp)
  libhypre-dev             # hypre's BoomerAMG (pulls in OpenMPI), a peer in benchmarks only (hypre_implicit_bench.cpp)
  python3-pytest python3-pil  # the Python module's tests (tests/python)
  python3-junitparser      # golden check --junit read back by a real JUnit reader (tests/cli/golden)
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

packages=("${product[@]}")
if [[ $part == test ]]; then
  packages+=("${tests[@]}")
  [[ ${CLOTHSIM_NO_CLIENTS:-0} == 1 ]] || packages+=("${clients[@]}")
fi

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
