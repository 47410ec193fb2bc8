#!/bin/sh
# Checks the OpenCL sources against .clang-format (they are formatted as C).
set -eu
status=0
for f in "$2"/*.cl; do
    if ! "$1" --assume-filename=kernel.c "$f" | cmp -s - "$f"; then
        echo "not formatted: $f (run: clang-format --assume-filename=kernel.c -i $f)"
        status=1
    fi
done
exit $status
