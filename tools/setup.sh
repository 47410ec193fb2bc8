#!/bin/sh
# impact-sph setup: installs what is missing (Debian 12 packages), builds, and
#   tools/setup.sh run   runs the default case (cases/beam_2d.yaml)
#   tools/setup.sh test  runs the test suite (ctest)
#   tools/setup.sh build only builds
# Safe to run again: installed packages are skipped and the build is incremental.
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD="$ROOT/build"
MODE=${1:-run}
PACKAGES="build-essential cmake pkg-config ocl-icd-opencl-dev opencl-c-headers \
pocl-opencl-icd clinfo libyaml-dev libhdf5-dev libcmocka-dev clang-format \
python3 python3-numpy python3-h5py python3-matplotlib python3-yaml python3-scipy \
openmpi-bin libopenmpi-dev libhdf5-openmpi-dev"
# Open MPI: `mpirun -np N build/sph run CASE` runs one case over N processes
# (README, "Over several processes"); without it the build is serial. The
# parallel HDF5 (beside the serial one, which the tools' h5py uses) lets the
# ranks write each snapshot together.
# The tests also open a run as ParaView does (tests/check_paraview.py), run
# the kernels under oclgrind (tests/check_oclgrind.sh) and fuzz the case
# reader with clang's libFuzzer (tests/fuzz_case.sh).
TEST_PACKAGES="python3-paraview oclgrind clang libclang-rt-14-dev"

case "$MODE" in
run | test | build) ;;
*)
    echo "usage: tools/setup.sh [run|test|build]" >&2
    exit 1
    ;;
esac

[ "$MODE" = test ] && PACKAGES="$PACKAGES $TEST_PACKAGES"
missing=""
for p in $PACKAGES; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $p"
    fi
done
if [ -n "$missing" ]; then
    echo "setup: installing$missing"
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null; then SUDO=sudo; else
            echo "setup: missing packages:$missing; run this script as root (or install sudo)" >&2
            exit 1
        fi
    fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing
fi

JOBS=$(nproc 2>/dev/null || echo 2)
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$BUILD" -j "$JOBS"

case "$MODE" in
run)
    cd "$ROOT"
    exec "$BUILD/sph" run cases/beam_2d.yaml
    ;;
test)
    cd "$BUILD"
    exec ctest --output-on-failure -j "$JOBS"
    ;;
esac
