#!/usr/bin/python3
"""Runs `sph` and asserts on its exit status, its messages and summary.json.

usage: check_run.py SPH [sph arguments ...] -- [--exit N] [--stderr TEXT]
                    [--key NAME MIN MAX] [--text NAME VALUE] [--file NAME]
                    [--first FILE COLUMN MIN MAX]
"""
import csv
import json
import os
import subprocess
import sys


def main():
    argv = sys.argv[1:]
    if "--" not in argv:
        sys.exit(__doc__)
    cut = argv.index("--")
    command, checks = argv[:cut], argv[cut + 1:]
    proc = subprocess.run(command, capture_output=True, text=True)
    sys.stdout.write(proc.stdout)
    sys.stdout.write(proc.stderr)
    out = command[command.index("--out") + 1] if "--out" in command else None
    failures = []
    expected_exit = 0
    i = 0
    while i < len(checks):
        what = checks[i]
        if what == "--exit":
            expected_exit = int(checks[i + 1])
            i += 2
        elif what == "--stderr":
            if checks[i + 1] not in proc.stderr:
                failures.append(f"stderr lacks {checks[i + 1]!r}")
            i += 2
        elif what == "--file":
            path = os.path.join(out, checks[i + 1])
            if not os.path.isfile(path) or os.path.getsize(path) == 0:
                failures.append(f"{path} missing or empty")
            i += 2
        elif what == "--key":
            key, low, high = checks[i + 1], float(checks[i + 2]), float(checks[i + 3])
            with open(os.path.join(out, "summary.json")) as f:
                value = json.load(f).get(key)
            if value is None or not low <= value <= high:
                failures.append(f"summary {key} = {value}, expected in [{low}, {high}]")
            else:
                print(f"check: {key} = {value:.6g} in [{low:g}, {high:g}]")
            i += 4
        elif what == "--first":  # a CSV column's value in the first data row
            path, column = os.path.join(out, checks[i + 1]), checks[i + 2]
            low, high = float(checks[i + 3]), float(checks[i + 4])
            try:
                with open(path, newline="") as f:
                    value = float(next(csv.DictReader(f))[column])
            except (OSError, StopIteration, KeyError, ValueError) as e:
                value = None
                failures.append(f"{path}: no first-row {column} ({e})")
            if value is not None and not low <= value <= high:
                failures.append(f"{path} first-row {column} = {value}, expected in [{low}, {high}]")
            elif value is not None:
                print(f"check: {path} first-row {column} = {value:.6g} in [{low:g}, {high:g}]")
            i += 5
        elif what == "--text":
            key, expected = checks[i + 1], checks[i + 2]
            try:
                with open(os.path.join(out, "summary.json")) as f:
                    value = json.load(f).get(key)
            except (OSError, ValueError) as e:
                value = f"(no readable summary.json: {e})"
            if value != expected:
                failures.append(f"summary {key} = {value!r}, expected {expected!r}")
            i += 3
        else:
            sys.exit(f"check_run: unknown check {what}")
    if proc.returncode != expected_exit:
        failures.append(f"exit status {proc.returncode}, expected {expected_exit}")
    for f in failures:
        print("FAIL: " + f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
