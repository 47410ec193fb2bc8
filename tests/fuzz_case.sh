#!/usr/bin/env bash
# Fuzzes case loading, validation, the resolved-case writer and the scene
# estimates and fill (tests/fuzz_case.c) with libFuzzer, ASan and UBSan. No
# OpenCL device is used.
#
#   tests/fuzz_case.sh SOURCE_DIR WORK_DIR [SECONDS [LIBFUZZER_FLAG...]]
#
# Builds WORK_DIR/fuzz_case, seeds WORK_DIR/seeds from SOURCE_DIR/cases/*.yaml,
# grows WORK_DIR/corpus (kept between runs) for SECONDS (default 60), and
# leaves any crashing input in WORK_DIR/artifacts/ and the log in
# WORK_DIR/fuzz.log. Extra arguments go to libFuzzer (e.g. -fork=8).
# Exit: 0 clean, 1 a crash, leak, timeout, sanitizer report or build error,
# 2 usage, 77 clang or libFuzzer missing (ctest: SKIP_RETURN_CODE 77).
set -u

if [ $# -lt 2 ]; then
    echo "usage: $0 SOURCE_DIR WORK_DIR [SECONDS [LIBFUZZER_FLAG...]]" >&2
    exit 2
fi
SOURCE_DIR=$(cd "$1" && pwd) || exit 2
mkdir -p "$2" || exit 2
WORK_DIR=$(cd "$2" && pwd) || exit 2
SECONDS_TO_RUN=${3:-60}
shift $(($# < 3 ? $# : 3))
case $SECONDS_TO_RUN in
'' | *[!0-9]*)
    echo "$0: SECONDS must be a whole number, got '$SECONDS_TO_RUN'" >&2
    exit 2
    ;;
esac

CC=${FUZZ_CC:-clang}
if ! command -v "$CC" >/dev/null 2>&1; then
    echo "SKIP: $CC not found (the case fuzzer needs clang with libFuzzer)"
    exit 77
fi
PROBE_DIR=$(mktemp -d "${TMPDIR:-/tmp}/fuzz_case_probe.XXXXXX") || exit 1
trap 'rm -rf "$PROBE_DIR"' EXIT
printf '#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { return 0; }\n' \
    >"$PROBE_DIR/probe.c"
if ! "$CC" -fsanitize=fuzzer,address,undefined "$PROBE_DIR/probe.c" -o "$PROBE_DIR/probe" \
    >"$PROBE_DIR/probe.log" 2>&1; then
    echo "SKIP: $CC cannot build a libFuzzer target with ASan and UBSan:"
    sed 's/^/  /' "$PROBE_DIR/probe.log" | head -5
    exit 77
fi

# HDF5's headers are not needed by the sources below; they are passed in case
# a header comes to include them.
read -ra HDF5_FLAGS <<<"$(pkg-config --cflags hdf5 2>/dev/null || echo -I/usr/include/hdf5/serial)"
read -ra HDF5_LIBS <<<"$(pkg-config --libs hdf5 2>/dev/null || echo -lhdf5)"
SANITIZE=-fsanitize=fuzzer,address,undefined
CFLAGS=(-std=c11 -g -O1 "$SANITIZE" -fno-sanitize-recover=undefined
    -fno-omit-frame-pointer -Wall -Wextra -Wno-unused-parameter
    -D_DEFAULT_SOURCE -DCL_TARGET_OPENCL_VERSION=120 "-DSPH_SOURCE_DIR=\"$SOURCE_DIR\""
    -I"$SOURCE_DIR/include" -I"$SOURCE_DIR/host" "${HDF5_FLAGS[@]}")
# case.c, scene.c and grading.c are what is fuzzed; state.c has
# solver_max_sound_speed (scene_estimate's step count), and device.c and
# fields.c are what state.c links against. Nothing opens a device.
SOURCES=(case.c scene.c grading.c state.c device.c fields.c)
BINARY=$WORK_DIR/fuzz_case
echo "building $BINARY"
if ! "$CC" "${CFLAGS[@]}" "$SOURCE_DIR/tests/fuzz_case.c" "${SOURCES[@]/#/$SOURCE_DIR/host/}" \
    -o "$BINARY" -lyaml -lOpenCL -lm >"$WORK_DIR/build.log" 2>&1; then
    if ! grep -q 'undefined reference' "$WORK_DIR/build.log"; then
        cat "$WORK_DIR/build.log" >&2
        echo "FAIL: the case fuzzer does not build" >&2
        exit 1
    fi
    # A host source came to need another: link them all (but main.c).
    echo "note: the minimal source set does not link; building with every host source"
    ALL=()
    for f in "$SOURCE_DIR"/host/*.c; do
        [ "$(basename "$f")" = main.c ] || ALL+=("$f")
    done
    if ! "$CC" "${CFLAGS[@]}" "$SOURCE_DIR/tests/fuzz_case.c" "${ALL[@]}" -o "$BINARY" \
        -lyaml -lOpenCL "${HDF5_LIBS[@]}" -lm >"$WORK_DIR/build.log" 2>&1; then
        cat "$WORK_DIR/build.log" >&2
        echo "FAIL: the case fuzzer does not build" >&2
        exit 1
    fi
fi

# Seeds: the example cases as they are, and each with one fixed --set
# override picked by a leading control byte (tests/fuzz_case.c).
SEEDS=$WORK_DIR/seeds
CORPUS=$WORK_DIR/corpus
ARTIFACTS=$WORK_DIR/artifacts
FUZZ_TMP=$WORK_DIR/tmp
rm -rf "$SEEDS" "$FUZZ_TMP"
mkdir -p "$SEEDS" "$CORPUS" "$ARTIFACTS" "$FUZZ_TMP" || exit 1
# Leading bytes 0x01-0x1f (not tab, newline, return) select the override.
SELECTORS=(1 2 3 4 5 6 7 8 11 12 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31)
i=0
for f in "$SOURCE_DIR"/cases/*.yaml; do
    [ -e "$f" ] || continue
    stem=$(basename "$f" .yaml)
    cp "$f" "$SEEDS/$stem.yaml"
    s=${SELECTORS[i % ${#SELECTORS[@]}]}
    { printf '%b' "\\0$(printf '%03o' "$s")"; cat "$f"; } >"$SEEDS/$stem.set$s.yaml"
    i=$((i + 1))
done
# Every override on one small case.
if [ -f "$SOURCE_DIR/cases/beam_2d.yaml" ]; then
    for s in "${SELECTORS[@]}"; do
        { printf '%b' "\\0$(printf '%03o' "$s")"; cat "$SOURCE_DIR/cases/beam_2d.yaml"; } \
            >"$SEEDS/beam_2d.all$s.yaml"
    done
fi

DICT=$SOURCE_DIR/tests/fuzz/case.dict
DICT_FLAG=()
[ -f "$DICT" ] && DICT_FLAG=(-dict="$DICT")
LOG=$WORK_DIR/fuzz.log
echo "fuzzing for $SECONDS_TO_RUN s (corpus $CORPUS, log $LOG)"
# libFuzzer's own error exit code is 77 by default: made 1 here so that a
# crash is never taken for a skip.
TMPDIR=$FUZZ_TMP \
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:strict_string_checks=1} \
    UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
    "$BINARY" -max_total_time="$SECONDS_TO_RUN" -timeout=10 -rss_limit_mb=2048 \
    -error_exitcode=1 -timeout_exitcode=1 -print_final_stats=1 \
    -artifact_prefix="$ARTIFACTS/" "${DICT_FLAG[@]}" "$@" "$CORPUS" "$SEEDS" >"$LOG" 2>&1
STATUS=$?

# The last status line and the final statistics.
grep -E '^#[0-9]+.*(DONE|pulse|NEW|REDUCE)' "$LOG" | tail -1
grep -E '^stat::' "$LOG"
echo "corpus directory: $(find "$CORPUS" -type f | wc -l) files (libFuzzer's corp: counts the seeds too)"
if [ $STATUS -eq 72 ]; then
    echo "FAIL: interrupted (log $LOG)" >&2
    exit 1
fi
if [ $STATUS -ne 0 ] || grep -qE 'runtime error:|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|SUMMARY: ' "$LOG"; then
    grep -nE 'runtime error:|ERROR:|SUMMARY:|fuzz_case:|Test unit written' "$LOG" | head -20 >&2
    echo "FAIL: the case fuzzer found a problem (libFuzzer exit $STATUS; log $LOG;" \
        "inputs in $ARTIFACTS)" >&2
    exit 1
fi
echo "PASS: no crash, leak, timeout or sanitizer report in $SECONDS_TO_RUN s"

# The corpus directory keeps every input that once added coverage: past
# 2000 files it is minimised (libFuzzer -merge=1) to the ones still needed.
FILES=$(find "$CORPUS" -type f | wc -l)
if [ "$FILES" -gt 2000 ]; then
    rm -rf "$CORPUS.merged" && mkdir -p "$CORPUS.merged" || exit 1
    if TMPDIR=$FUZZ_TMP "$BINARY" -merge=1 -timeout=10 -rss_limit_mb=2048 "$CORPUS.merged" \
        "$CORPUS" >"$WORK_DIR/merge.log" 2>&1; then
        rm -rf "$CORPUS" && mv "$CORPUS.merged" "$CORPUS"
        echo "corpus directory minimised from $FILES to $(find "$CORPUS" -type f | wc -l) files"
    else
        rm -rf "$CORPUS.merged"
        echo "note: minimising the corpus failed (see $WORK_DIR/merge.log); it is left as it was"
    fi
fi
exit 0
