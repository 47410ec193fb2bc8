#!/bin/sh
# A few steps of a case under oclgrind (an OpenCL simulator that checks
# every access like a strict GPU would): fails on any data race, read of
# uninitialised memory, out-of-bounds access or API error it reports, and
# on a run that does not complete. Exits 77 (ctest: skipped) when oclgrind
# is not installed (Debian package oclgrind; tools/setup.sh test installs it).
# usage: check_oclgrind.sh SPH OUT_DIR CASE [sph run options ...]
# With SPH_OCLGRIND_RANKS=N the run is over N MPI processes, each under
# oclgrind (the halo kernels, kernels/halo.cl); skipped without mpirun.
sph=$1 out=$2 case=$3
shift 3
if ! command -v oclgrind >/dev/null 2>&1; then
    echo "oclgrind not installed: skipped"
    exit 77
fi
launch=""
if [ -n "${SPH_OCLGRIND_RANKS:-}" ]; then
    if ! command -v mpirun >/dev/null 2>&1; then
        echo "mpirun not installed: skipped"
        exit 77
    fi
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    launch="mpirun --oversubscribe --bind-to none -np $SPH_OCLGRIND_RANKS -x SPH_BUILD_OPTIONS"
fi
log=$out.oclgrind.log
rm -rf "$out"
# -cl-opt-disable: oclgrind's checks map errors to source lines without the
# optimiser's reordering
export SPH_BUILD_OPTIONS=-cl-opt-disable
$launch oclgrind --data-races --uninitialized --check-api \
    --max-errors 20 "$sph" run "$case" --out "$out" --quiet "$@" >"$log" 2>&1
status=$?
reports=$(grep -c "Kernel:\|^Oclgrind - \|API error" "$log")
tail -1 "$log"
if [ "$status" -ne 0 ] || [ "$reports" -ne 0 ]; then
    echo "FAIL: exit $status, $reports oclgrind reports (log: $log):"
    head -40 "$log"
    exit 1
fi
echo "oclgrind: no race, uninitialised read, out-of-bounds access or API error"
