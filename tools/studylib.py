"""What the study tools share: running `sph` on a case, reading a run's
CSV columns with errors that name the file and line, writing a table as
CSV and Markdown, the Richardson estimate from three spacings, and a
sphere's resistance over a window of its ballistics.csv
(tools/beam_study.py, tools/taylor_study.py, tools/penetration_study.py,
tools/towed_sphere_drag.py, tools/plot_run.py, tools/compare_runs.py)."""
import csv
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPH = os.environ.get("SPH", os.path.join(ROOT, "build", "sph"))


def run(case, out, sets, tool):
    """Runs `sph run case --out out --set ...`; returns its summary.json. A
    run that went unstable (exit 3) still has a summary; other failures stop
    the study with `tool`'s name."""
    cmd = [SPH, "run", case, "--out", out, "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    print("$ " + " ".join(cmd), flush=True)
    proc = subprocess.run(cmd, capture_output=True, text=True)
    sys.stdout.write(proc.stdout)
    if proc.returncode not in (0, 3):
        sys.stderr.write(proc.stderr)
        sys.exit(f"{tool}: sph exited with {proc.returncode}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def read_columns(path, tool, required=None, optional=()):
    """{column: [float, ...]} of a CSV file with a header row (history.csv,
    ballistics.csv, or another code's curve): the `required` and `optional`
    columns, or every column when `required` is None. Exits naming `tool`,
    the file and the line on a missing file or column, a cell that is not
    a number, or a file without rows."""
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            header = reader.fieldnames or []
            wanted = list(header) if required is None else list(required)
            missing = [c for c in wanted if c not in header]
            if missing:
                sys.exit(f"{tool}: {path}:1: expected the columns {', '.join(wanted)}; "
                         f"missing {', '.join(missing)}")
            keep = wanted + [c for c in optional if c in header and c not in wanted]
            columns = {c: [] for c in keep}
            for line, row in enumerate(reader, start=2):
                for c in keep:
                    try:
                        columns[c].append(float(row[c]))
                    except (TypeError, ValueError):
                        sys.exit(f"{tool}: {path}:{line}: expected a number in column {c}, "
                                 f"found {row[c]!r}")
    except OSError as e:
        sys.exit(f"{tool}: cannot read {path}: {e.strerror}")
    if not keep or not columns[keep[0]]:
        sys.exit(f"{tool}: {path} has no rows")
    return columns


def resistance_in_window(rows, d, t0, t1):
    """The force on a sphere of diameter d (m) over its frontal area pi d^2 / 4,
    from ballistics.csv rows (decelerating_force_N) with t0 <= time_s <= t1:
    its mean and standard deviation, Pa."""
    forces = [float(r["decelerating_force_N"]) for r in rows if t0 <= float(r["time_s"]) <= t1]
    area = math.pi * d * d / 4
    mean = sum(forces) / len(forces)
    spread = math.sqrt(sum((f - mean) ** 2 for f in forces) / len(forces))
    return mean / area, spread / area


def write_table(folder, name, header, rows):
    """folder/name.csv and folder/name.md; prints the Markdown."""
    with open(os.path.join(folder, name + ".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    with open(os.path.join(folder, name + ".md"), "w") as f:
        f.write("| " + " | ".join(header) + " |\n")
        f.write("|" + " --- |" * len(header) + "\n")
        for r in rows:
            f.write("| " + " | ".join(str(x) for x in r) + " |\n")
    print(open(os.path.join(folder, name + ".md")).read())


def richardson(spacings, values):
    """(limit, observed order) from three values at spacings h1 > h2 > h3
    refined by one constant ratio, f = f_limit + C h^p; None when the ratio
    is not constant or the two steps differ in sign (no order exists)."""
    (h1, h2, h3), (f1, f2, f3) = spacings, values
    ratio = h1 / h2
    if abs(h2 / h3 - ratio) > 1e-9 * ratio or (f1 - f2) * (f2 - f3) <= 0:
        return None
    order = math.log((f1 - f2) / (f2 - f3)) / math.log(ratio)
    return f3 + (f3 - f2) / (ratio ** order - 1), order
