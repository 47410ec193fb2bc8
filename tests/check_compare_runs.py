#!/usr/bin/python3
"""tools/compare_runs.py on histories whose answers are known: a reference
depth A sin(w t) (P_max = A at t = pi / (2 w)), read between its rows to
the sine within the table's 0.01 um, a run 2% shallower at every time
(every cell and P_max -2.00%, the same t(P_max)), a run whose history
stops before its maximum (blank past its end, its P_max marked as not yet
one), one deepest at its last row but already moving back (a maximum, not
marked), and two files it must refuse: one without penetration_m (an error
naming the file, line 1 and the column) and one with a word where a number
belongs (naming the file and line 4).

usage: check_compare_runs.py TOOL WORK
"""
import math
import os
import subprocess
import sys

A = 100.0e-6  # m
OMEGA = math.pi / (2 * 500.0e-9)  # 1/s: the maximum at 500 ns
END = 1000.0e-9  # s


def write_history(path, scale, end, velocity=True, columns=None, bad_row=None):
    header = columns or (["time_s", "penetration_m"] + (["velocity_m_per_s"] if velocity else []))
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for k in range(201):
            t = end * k / 200
            row = [t, scale * A * math.sin(OMEGA * t), scale * A * OMEGA * math.cos(OMEGA * t)]
            cells = [f"{v:.9e}" for v in row[:len(header)]]
            if bad_row is not None and k == bad_row:
                cells[1] = "deep"
            f.write(",".join(cells) + "\n")


def run(tool, *args):
    return subprocess.run([sys.executable, tool, *args], capture_output=True, text=True)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    tool, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    ref, shallow, short = (os.path.join(work, n) for n in ("ref.csv", "shallow.csv", "short.csv"))
    write_history(ref, 1.0, END)
    write_history(shallow, 0.98, END)
    write_history(short, 1.0, 0.3 * END, velocity=False)
    png = os.path.join(work, "compare.png")
    times = (102.0e-9, 251.0e-9, 403.0e-9)  # off every file's rows: interpolated
    proc = run(tool, ref, shallow, short, "--label", "ref", "shallow", "short", "--times",
               *(repr(t) for t in times), "--out", png)
    print(proc.stdout, proc.stderr)
    failures = []
    if proc.returncode != 0:
        failures.append(f"exit {proc.returncode} on good input")
    rows = {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
            for line in proc.stdout.splitlines() if line.startswith("| ") and "---" not in line}
    shallow_row, short_row = rows.get("shallow", []), rows.get("short", [])
    if len(shallow_row) != 5 or any("(-2.00%)" not in c for c in shallow_row[:4]):
        failures.append(f"the 2% shallower run's cells are not all -2.00%: {shallow_row}")
    # linear interpolation between rows 5 ns apart is within A (w dt)^2 / 8 = 0.003 um of
    # the sine; the table prints 0.01 um
    ref_row = rows.get("ref", [""] * 5)
    for t, cell in zip(times, ref_row):
        exact = 1e6 * A * math.sin(OMEGA * t)
        if not cell or abs(float(cell) - exact) > 0.011:
            failures.append(f"reference depth at {1e9 * t:.0f} ns: {cell} um, exact {exact:.3f}")
    if ref_row[4] != "500" or shallow_row[4:] != ["500"]:
        failures.append("t(P_max) is not 500 ns for both full runs")
    if len(short_row) != 5 or short_row[2] != "" or "not yet a maximum" not in short_row[3]:
        failures.append(f"the short run is not blank past its end and unmarked: {short_row}")
    # deepest at its last row, but already moving back there: a maximum
    turning = os.path.join(work, "turning.csv")
    with open(turning, "w") as f:
        f.write("time_s,penetration_m,velocity_m_per_s\n0,0,10\n1e-9,5e-6,1\n2e-9,5.1e-6,-0.1\n")
    proc = run(tool, turning, turning, "--out", png)
    if proc.returncode != 0 or "not yet" in proc.stdout or "5.10 (+0.00%)" not in proc.stdout:
        failures.append(f"a history that ends turning back is not a maximum: {proc.stdout!r}")
    if not os.path.isfile(png) or os.path.getsize(png) < 1000:
        failures.append("no plot written")
    missing = os.path.join(work, "missing.csv")
    write_history(missing, 1.0, END, columns=["time_s", "depth_m"])
    proc = run(tool, ref, missing, "--out", png)
    if proc.returncode != 1 or f"{missing}:1:" not in proc.stderr or "penetration_m" not in proc.stderr:
        failures.append(f"a file without penetration_m: exit {proc.returncode}, {proc.stderr!r}")
    word = os.path.join(work, "word.csv")
    write_history(word, 1.0, END, bad_row=2)
    proc = run(tool, ref, word, "--out", png)
    if proc.returncode != 1 or f"{word}:4:" not in proc.stderr:
        failures.append(f"a word in row 4: exit {proc.returncode}, {proc.stderr!r}")
    for failure in failures:
        print("check_compare_runs:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
