#!/bin/sh
# A few steps of a case under oclgrind (an OpenCL simulator that checks
# every access like a strict GPU would): fails on any data race, read of
# uninitialised memory, out-of-bounds access or API error it reports, and
# on a run that does not complete. Exits 77 (ctest: skipped) when oclgrind
# is not installed (Debian package oclgrind; tools/setup.sh test installs it).
# usage: check_oclgrind.sh SPH OUT_DIR CASE [sph run options ...]
sph=$1 out=$2 case=$3
shift 3
if ! command -v oclgrind >/dev/null 2>&1; then
    echo "oclgrind not installed: skipped"
    exit 77
fi
log=$out.oclgrind.log
rm -rf "$out"
# -cl-opt-disable: oclgrind's checks map errors to source lines without the
# optimiser's reordering
SPH_BUILD_OPTIONS=-cl-opt-disable oclgrind --data-races --uninitialized --check-api \
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
