#!/usr/bin/python3
"""Micro-particle penetration studies (issue: penetration into gelatin and
SEBS gel), each one command, tables and plots under results/penetration/.

  tools/penetration_study.py run        --case gelatin|sebs [--d D] [--v0 V] [--n N]
  tools/penetration_study.py sweep      --case gelatin|sebs [--v0 ...] [--d ...] [--n N]
  tools/penetration_study.py sebs       [--n N]      the three fitting trajectories
  tools/penetration_study.py convergence --case gelatin [--n 6 8 10 12 16]
  tools/penetration_study.py domain     --case gelatin [--n N]   1x and 2x target
  tools/penetration_study.py grading    --case gelatin [--n N]   graded vs uniform lattice
  tools/penetration_study.py resistance --case gelatin [--v0 V] [--n 8 16 24 32]
                                        [--travel 5] the sphere pushed at constant
                                        speed V (projectile.motion: prescribed)
                                        through 5 d: its steady resistance F / (pi R^2)
                                        at each spacing, Richardson limit, order
  tools/penetration_study.py resistance-chart --tables A.csv B.csv ... --labels ...
                                        --limit MPa [--out PNG]: several resistance
                                        tables on one chart against one limit
  tools/penetration_study.py calibrate  --case gelatin --parameter KEY --bracket LOW HIGH
                                        [--n N]: KEY fitted (bounded Brent search in
                                        log KEY) to the model's depth-time curve of the
                                        designated shot (d, v0 the case's), RMS misfit
                                        [--tolerance 0.01 in log KEY]
  common: [--results DIR] [--set key=value ...]

Every run is cases/gelatin_silica.yaml or cases/sebs_steel.yaml with the
scene scaled to the sphere (in units of its diameter d: target 16 d in
radius and at least 32 d deep, spacing dx = d / n within 2.2 d of the axis
and to 16 d or 1.5 (SEBS: 2) times the analytical model's depth below the
surface, doubling outwards up to 8 dx), the sphere's nose on the surface,
and the end time 2 (SEBS: 3.5) times the model's time of maximum depth
(REACH). The depth is the nose's depth below the undisturbed surface (the
distance moved since contact), compared with the models' P + d/2
(REFERENCES.md 3; tools/penetration_models.py, nose=True).

Models drawn: gelatin, Poncelet Cd = 0.375, R = 21 MPa; SEBS, modified
Clift-Gauvin eta = 4.5e-2 Pa s, R = 25 MPa (approach b) and Poncelet
Cd = 0.8, R = 33.7 MPa.
"""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import penetration_models as pm  # noqa: E402
import studylib  # noqa: E402
from studylib import write_table  # noqa: E402
import matplotlib  # noqa: E402
import numpy as np  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = {
    # case file, target, projectile density, model, parameters, default d and v0
    "gelatin": ("gelatin_silica.yaml", pm.GELATIN, pm.SILICA, "poncelet", pm.GELATIN_PONCELET,
                7.38e-6, 1290.0),
    "sebs": ("sebs_steel.yaml", pm.SEBS, pm.STEEL, "clift_gauvin", pm.SEBS_CLIFT_GAUVIN, 13e-6,
             630.0),
}
# How far past the model's P_max and its time the scene reaches (fine region
# depth, end time): the SPH sphere in the thesis' SEBS material with its
# viscosity goes about 2.8 times the fitted model's depth at 630 m/s (425
# against 153 um) and stops at about 3 times its time, and further at
# 440 m/s (docs/validation_penetration.md), so its scene reaches further.
REACH = {"gelatin": (1.5, 2.0), "sebs": (4.0, 5.0)}
GELATIN_SWEEP = [200, 400, 600, 800, 1000, 1290, 1500]


def model_depth(case, d, v0):
    """(P_max + d/2, time of P_max) of the case's analytical model."""
    _, target, rho_p, model, params, _, _ = CASES[case]
    return pm.max_depth(model, params, pm.Projectile(d, rho_p), target, v0, nose=True)


def scene_sets(case, d, v0, n, domain=1.0, graded=True):
    """--set overrides that scale the case's scene to sphere d at v0."""
    p_model, t_model = model_depth(case, d, v0)
    depth_reach, time_reach = REACH[case]
    radius, depth = 16 * d * domain, 32 * d * domain
    fine_depth = max(16 * d, depth_reach * p_model)
    sets = [
        f"projectile.diameter={d!r}", f"projectile.centre=[0,{0.5 * d!r}]",
        f"projectile.velocity=[0,{-v0!r}]", f"numerics.dx={d / n!r}",
        f"bodies.gel.min=[0,{-max(depth, 2 * fine_depth)!r}]", f"bodies.gel.max=[{radius!r},0]",
        f"numerics.end_time={time_reach * t_model!r}",
        f"output.snapshot_interval={time_reach * t_model / 20!r}",
        f"projectile.cavity_probe_spacing={d!r}",
    ]
    body_depth = max(depth, 2 * fine_depth)
    sets[4] = f"bodies.gel.min=[0,{-body_depth!r}]"
    if graded:
        sets += [f"bodies.gel.grading.fine_min=[0,{-fine_depth!r}]",
                 f"bodies.gel.grading.fine_max=[{2.2 * d!r},0]"]
    else:  # the fine box is the whole body: one level
        sets += [f"bodies.gel.grading.fine_min=[0,{-body_depth!r}]",
                 f"bodies.gel.grading.fine_max=[{radius!r},0]"]
    return sets


def run(args, case, d, v0, n, label, domain=1.0, graded=True, extra=()):
    """Runs one scene (the case scaled to d, v0, n, then `extra` and the
    command line's --set overrides); returns (summary, ballistics rows)."""
    out = os.path.join(args.results, "penetration", "runs", label)
    sets = scene_sets(case, d, v0, n, domain, graded) + list(extra) + list(args.set)
    summary = studylib.run(os.path.join(ROOT, "cases", CASES[case][0]), out, sets,
                           "penetration_study")
    with open(os.path.join(out, "ballistics.csv")) as f:
        rows = list(csv.DictReader(f))
    return summary, rows


def status_note(s):
    """The run's status, with what makes its P_max not a converged value:
    the nose in the graded lattice's coarse shells, or P_max at the end."""
    notes = [s["status"]]
    if "nose_left_fine_region_time_s" in s:
        notes.append(f"nose in coarse shells from {1e9 * s['nose_left_fine_region_time_s']:.0f} ns")
    if s["time_of_max_penetration_s"] >= 0.99 * s["end_time_s"]:
        notes.append("P_max at the end time: a lower bound")
    return "; ".join(notes)


def describe(s, d):
    return [f"{1e6 * s['max_penetration_m']:.2f}", f"{s['max_penetration_m'] / d:.3f}",
            f"{1e9 * s['time_of_max_penetration_s']:.0f}",
            f"{1e6 * s['max_cavity_diameter_m']:.1f}", f"{1e6 * s['max_damaged_diameter_m']:.1f}",
            f"{s['momentum_error']:.1e}", f"{s['energy_drift']:.3f}",
            f"{s['artificial_viscosity_work_fraction']:.2f}", s["particles"], s["steps"],
            f"{s['wall_time_s']:.0f}", status_note(s)]


HEADER = ["P_max (um)", "P_max/d", "t(P_max) (ns)", "D1 max (um)", "D2 max (um)",
          "momentum error", "energy drift", "AV work / KE0", "particles", "steps", "wall (s)",
          "status"]


def trajectory_plot(path, title, runs, case):
    """Depth and velocity against time, SPH (solid) and model (dashed)."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    _, target, rho_p, model, params, _, _ = CASES[case]
    for k, (label, d, v0, rows) in enumerate(runs):
        colour = f"C{k}"
        t = [1e9 * float(r["time_s"]) for r in rows]
        ax1.plot(t, [1e6 * float(r["penetration_m"]) for r in rows], colour, label=f"SPH {label}")
        ax2.plot(t, [float(r["velocity_m_per_s"]) for r in rows], colour)
        tm, pmod, vm = pm.trajectory(model, params, pm.Projectile(d, rho_p), target, v0,
                                     nose=True)
        ax1.plot(1e9 * tm, 1e6 * pmod, colour + "--", label=f"{model} {label}")
        ax2.plot(1e9 * tm, vm, colour + "--")
    ax1.set_xlabel("time (ns)")
    ax1.set_ylabel("penetration depth (um)")
    ax2.set_xlabel("time (ns)")
    ax2.set_ylabel("projectile velocity (m/s)")
    ax1.legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def folder(args):
    f = os.path.join(args.results, "penetration")
    os.makedirs(f, exist_ok=True)
    return f


def cmd_run(args):
    case = args.case
    d = args.d[0] if args.d else CASES[case][5]
    v0 = args.v0[0] if args.v0 else CASES[case][6]
    s, rows = run(args, case, d, v0, args.n[0], f"{case}_d{1e6 * d:g}_v{v0:g}_n{args.n[0]:g}")
    p_model, t_model = model_depth(case, d, v0)
    write_table(folder(args), f"{case}_run", ["d (um)", "v0 (m/s)", "model P_max (um)"] + HEADER,
                [[f"{1e6 * d:g}", f"{v0:g}", f"{1e6 * p_model:.2f}"] + describe(s, d)])
    trajectory_plot(os.path.join(folder(args), f"{case}_trajectory.png"),
                    f"{case}: d = {1e6 * d:g} um at {v0:g} m/s",
                    [(f"{1e6 * d:g} um, {v0:g} m/s", d, v0, rows)], case)


def cmd_sweep(args):
    case = args.case
    ds = args.d or [CASES[case][5]]
    vs = args.v0 or (GELATIN_SWEEP if case == "gelatin" else [215, 300, 440, 630, 735])
    table, points = [], []
    for d in ds:
        for v0 in vs:
            s, _ = run(args, case, d, v0, args.n[0], f"{case}_d{1e6 * d:g}_v{v0:g}_n{args.n[0]:g}")
            p_model, _ = model_depth(case, d, v0)
            err = s["max_penetration_m"] / p_model - 1
            table.append([f"{1e6 * d:g}", f"{v0:g}", f"{p_model / d:.3f}", f"{100 * err:+.1f}%"]
                         + describe(s, d))
            points.append((d, v0, s["max_penetration_m"] / d))
    write_table(folder(args), f"{case}_sweep",
                ["d (um)", "v0 (m/s)", "model P_max/d", "SPH vs model"] + HEADER, table)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    _, target, rho_p, model, params, _, _ = CASES[case]
    v = [50 + 10 * k for k in range(150)]
    for d in ds:
        curve = [pm.max_depth(model, params, pm.Projectile(d, rho_p), target, x,
                              nose=True)[0] / d for x in v]
        ax.plot(v, curve, "--", label=f"{model}, d = {1e6 * d:g} um")
        if case == "sebs":
            pon = [pm.max_depth("poncelet", pm.SEBS_PONCELET, pm.Projectile(d, rho_p), target, x,
                                nose=True)[0] / d for x in v]
            ax.plot(v, pon, ":", label=f"poncelet, d = {1e6 * d:g} um")
    for d in ds:
        xs = [p[1] for p in points if p[0] == d]
        ys = [p[2] for p in points if p[0] == d]
        ax.plot(xs, ys, "o", label=f"SPH, d = {1e6 * d:g} um")
    if case == "gelatin":
        ax.plot([1290], [67e-6 / 7.38e-6], "k*", ms=12, label="Veysset et al. 2018")
    ax.set_xlabel("impact velocity v0 (m/s)")
    ax.set_ylabel("P_max / d")
    ax.set_xlim(0, max(vs) * 1.1)
    ax.legend(fontsize=8)
    ax.set_title(f"{case}: normalised maximum depth")
    fig.tight_layout()
    fig.savefig(os.path.join(folder(args), f"{case}_sweep.png"), dpi=120)
    plt.close(fig)


def cmd_sebs(args):
    runs, table = [], []
    for d, v0 in pm.SEBS_FIT_CASES:
        s, rows = run(args, "sebs", d, v0, args.n[0], f"sebs_d{1e6 * d:g}_v{v0:g}_n{args.n[0]:g}")
        p_model, _ = model_depth("sebs", d, v0)
        p_pon, _ = pm.max_depth("poncelet", pm.SEBS_PONCELET, pm.Projectile(d, pm.STEEL),
                                pm.SEBS, v0, nose=True)
        table.append([f"{1e6 * d:g}", f"{v0:g}", f"{1e6 * p_model:.1f}", f"{1e6 * p_pon:.1f}",
                      f"{100 * (s['max_penetration_m'] / p_model - 1):+.1f}%"] + describe(s, d))
        runs.append((f"{1e6 * d:g} um, {v0:g} m/s", d, v0, rows))
    write_table(folder(args), "sebs_trajectories",
                ["d (um)", "v0 (m/s)", "Clift-Gauvin P_max (um)", "Poncelet P_max (um)",
                 "SPH vs Clift-Gauvin"] + HEADER, table)
    trajectory_plot(os.path.join(folder(args), "sebs_trajectories.png"),
                    "SEBS gel, steel spheres: SPH against modified Clift-Gauvin", runs, "sebs")


def cmd_convergence(args):
    case = args.case
    d, v0 = CASES[case][5], CASES[case][6]
    table, runs, depths, walls = [], [], [], []
    for n in args.n:
        s, rows = run(args, case, d, v0, n, f"{case}_n{n:g}")
        table.append([f"{n:g}", f"{1e6 * d / n:.4f}"] + describe(s, d))
        runs.append((f"d/dx = {n:g}", d, v0, rows))
        depths.append(s["max_penetration_m"])
        walls.append(s["wall_time_s"])
    fit, triple = spacing_limit(args.n, depths)
    if fit:
        note = (f"Richardson limit {1e6 * fit[0]:.2f} um, observed order {fit[1]:.2f} "
                f"(d/dx {', '.join(f'{args.n[i]:g}' for i in triple)})")
        for row, p in zip(table, depths):
            row.append(f"{100 * (p / fit[0] - 1):+.1f}%")
    else:
        note = "no Richardson limit: no three spacings with one ratio whose steps shrink"
        for row in table:
            row.append("")
    table.append(["limit", "", f"{1e6 * fit[0]:.2f}" if fit else ""]
                 + [""] * (len(HEADER) - 1) + [note])
    write_table(folder(args), f"{case}_convergence",
                ["d/dx", "dx (um)"] + HEADER + ["vs limit"], table)
    print(note)
    trajectory_plot(os.path.join(folder(args), f"{case}_convergence.png"),
                    f"{case}: convergence with spacing", runs, case)
    if fit:
        fig, ax = plt.subplots(figsize=(5.5, 4))
        error_against_cost(ax, walls, depths, fit[0], "|P_max / P_limit - 1|")
        for n, w, p in zip(args.n, walls, depths):
            ax.annotate(f"d/dx {n:g}", (w, max(abs(p / fit[0] - 1), 1e-4)), fontsize=8)
        ax.set_title(f"{case}: depth error against cost")
        fig.tight_layout()
        fig.savefig(os.path.join(folder(args), f"{case}_convergence_cost.png"), dpi=120)
        plt.close(fig)


def cmd_domain(args):
    case = args.case
    d, v0 = CASES[case][5], CASES[case][6]
    table = []
    for factor in (1.0, 2.0):
        s, _ = run(args, case, d, v0, args.n[0], f"{case}_domain{factor:g}", domain=factor)
        table.append([f"{16 * factor:g} d x {32 * factor:g} d"] + describe(s, d))
    write_table(folder(args), f"{case}_domain", ["target (radius x depth)"] + HEADER, table)


def cmd_grading(args):
    case = args.case
    d, v0 = CASES[case][5], CASES[case][6]
    table, runs = [], []
    for graded in (True, False):
        label = "graded" if graded else "uniform"
        s, rows = run(args, case, d, v0, args.n[0], f"{case}_{label}", graded=graded)
        table.append([label] + describe(s, d))
        runs.append((label, d, v0, rows))
    write_table(folder(args), f"{case}_grading", ["lattice"] + HEADER, table)
    trajectory_plot(os.path.join(folder(args), f"{case}_grading.png"),
                    f"{case}: graded against uniform lattice, d/dx = {args.n[0]:g}", runs, case)


def spacing_limit(n, values):
    """((limit, order), indices) from the finest three spacings d / n refined
    by one ratio (n in any order), or (None, None) unless there are three
    such and their steps shrink (a positive order)."""
    triples = [(i, j, k) for i in range(len(n)) for j in range(len(n)) for k in range(len(n))
               if n[i] < n[j] < n[k] and abs(n[j] / n[i] - n[k] / n[j]) < 1e-3 * n[k] / n[j]]
    if not triples:
        return None, None
    triple = max(triples, key=lambda t: n[t[2]])
    fit = studylib.richardson([1 / n[i] for i in triple], [values[i] for i in triple])
    return (fit, triple) if fit and fit[1] > 0 else (None, None)


def error_against_cost(ax, walls, values, limit, ylabel, label=None):
    """|value / limit - 1| against wall time, log-log (floored at 1e-4)."""
    ax.loglog(walls, [max(abs(v / limit - 1), 1e-4) for v in values], "o-", label=label)
    ax.set_xlabel("wall time on this machine (s)")
    ax.set_ylabel(ylabel)


def cmd_resistance(args):
    """The sphere held at v0 (projectile.motion: prescribed) through 5 d (--travel) of
    target: the inertial drag of the impact phase measured without the
    deceleration, so its convergence with spacing is seen directly."""
    case = args.case
    d = args.d[0] if args.d else CASES[case][5]
    v0 = args.v0[0] if args.v0 else 600.0
    rho = CASES[case][1].rho_t
    end = args.travel * d / v0
    table, values, walls = [], [], []
    for n in args.n:
        s, rows = run(args, case, d, v0, n, f"{case}_resistance_v{v0:g}_n{n:g}",
                      extra=["projectile.motion=prescribed", f"numerics.end_time={end!r}",
                             f"output.snapshot_interval={end / 5!r}"])
        r, _ = studylib.resistance_in_window(rows, d, 0.5 * end, end)
        values.append(r)
        walls.append(s["wall_time_s"])
        table.append([f"{n:g}", f"{1e6 * d / n:.3f}", f"{r / 1e6:.2f}",
                      f"{2 * r / (rho * v0 * v0):.3f}", f"{s['energy_drift']:.3f}",
                      f"{s['momentum_error']:.1e}", f"{s['artificial_viscosity_work_fraction']:.2f}",
                      s["particles"], s["steps"], f"{s['wall_time_s']:.0f}", s["status"]])
    fit, _ = spacing_limit(args.n, values)
    note = (f"Richardson limit {fit[0] / 1e6:.2f} MPa, observed order {fit[1]:.2f}" if fit else
            "no Richardson limit: no three spacings with one ratio whose steps shrink")
    table.append(["limit", "", f"{fit[0] / 1e6:.2f}" if fit else "", "", "", "", "", "", "", "",
                  note])
    write_table(folder(args), f"{case}_resistance_v{v0:g}",
                ["d/dx", "dx (um)", "F/(pi R^2) (MPa)", "2F/(rho v^2 pi R^2)", "energy drift",
                 "momentum error", "AV work / KE0", "particles", "steps", "wall (s)", "status"],
                table)
    print(note)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    left.plot([1 / n for n in args.n], [v / 1e6 for v in values], "o-", label="SPH")
    if fit:
        left.axhline(fit[0] / 1e6, ls="--", color="k",
                     label=f"Richardson limit (order {fit[1]:.2f})")
        error_against_cost(right, walls, values, fit[0], "|F / F_limit - 1|")
        right.set_title("error against cost")
    left.set_xlim(left=0)
    left.set_xlabel("dx / d")
    left.set_ylabel("steady resistance F / (pi R^2) (MPa)")
    left.set_title(f"{case}: sphere held at {v0:g} m/s, mean over "
                   f"{args.travel / 2:g}-{args.travel:g} d of travel")
    left.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(folder(args), f"{case}_resistance_v{v0:g}.png"), dpi=120)
    plt.close(fig)


def trajectory_misfit(rows, case, d, v0):
    """RMS distance between the SPH depth-time curve and the model's, over the
    model's flight (0 to its time of P_max, 101 times), over the model's P_max."""
    _, target, rho_p, model, params, _, _ = CASES[case]
    t_model, p_model, _ = pm.trajectory(model, params, pm.Projectile(d, rho_p), target, v0,
                                        nose=True)
    t_model, p_model = t_model[::5], p_model[::5]
    t_sph = np.array([float(r["time_s"]) for r in rows])
    p_sph = np.array([float(r["penetration_m"]) for r in rows])
    if t_sph[-1] < t_model[-1]:
        sys.exit(f"penetration_study: the run ended at {1e9 * t_sph[-1]:.0f} ns, before the "
                 f"model's time of P_max ({1e9 * t_model[-1]:.0f} ns): no misfit to compare")
    error = np.interp(t_model, t_sph, p_sph) - p_model
    return math.sqrt(float(np.mean(error * error))) / p_model[-1]


def cmd_calibrate(args):
    """One material parameter fitted to the designated shot's depth-time curve
    (REFERENCES.md 3): a bounded Brent search in log(parameter) on --parameter
    between the two --bracket values, at d/dx --n, each trial a full run."""
    if not args.parameter or not args.bracket or len(args.bracket) != 2:
        sys.exit("penetration_study: calibrate needs --parameter KEY and --bracket LOW HIGH")
    case = args.case
    d = args.d[0] if args.d else CASES[case][5]
    v0 = args.v0[0] if args.v0 else CASES[case][6]
    n = args.n[0]
    trials = []

    def misfit(log_value):
        value = math.exp(log_value)
        label = f"{case}_calibrate_n{n:g}_{len(trials)}"
        s, rows = run(args, case, d, v0, n, label, extra=[f"{args.parameter}={value!r}"])
        m = trajectory_misfit(rows, case, d, v0)
        trials.append([f"{value:.6g}", f"{m:.4f}"] + describe(s, d))
        print(f"calibrate: {args.parameter} = {value:.6g}: misfit {m:.4f}, "
              f"P_max {1e6 * s['max_penetration_m']:.2f} um", flush=True)
        return m

    from scipy.optimize import minimize_scalar
    best = minimize_scalar(misfit, bounds=tuple(math.log(b) for b in args.bracket),
                           method="bounded", options={"xatol": args.tolerance})
    p_model, t_model = model_depth(case, d, v0)
    trials.append([f"best {math.exp(best.x):.6g}", f"{best.fun:.4f}",
                   f"model P_max {1e6 * p_model:.2f} um at {1e9 * t_model:.0f} ns"]
                  + [""] * (len(HEADER) - 1))
    write_table(folder(args), f"{case}_calibrate_n{n:g}",
                [args.parameter, "RMS depth misfit / model P_max"] + HEADER, trials)
    print(f"calibrate: best {args.parameter} = {math.exp(best.x):.6g} "
          f"(misfit {best.fun:.4f} of the model's P_max)")


def cmd_resistance_chart(args):
    """Resistance tables (from `resistance`) against one limit: resistance
    against dx / d, and its error against wall time."""
    if not args.tables or len(args.labels or []) != len(args.tables) or args.limit is None:
        sys.exit("penetration_study: resistance-chart needs --tables, as many --labels "
                 "and --limit (MPa)")
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for path, label in zip(args.tables, args.labels):
        with open(path, newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["d/dx"] != "limit"]
        n = [float(r["d/dx"]) for r in rows]
        value = [float(r["F/(pi R^2) (MPa)"]) for r in rows]
        wall = [float(r["wall (s)"]) for r in rows]
        left.plot([1 / k for k in n], value, "o-", label=label)
        error_against_cost(right, wall, value, args.limit, "|F / F_limit - 1|", label)
    left.axhline(args.limit, ls="--", color="k", label=f"limit {args.limit:g} MPa")
    left.set_xlim(left=0)
    left.set_xlabel("dx / d")
    left.set_ylabel("steady resistance F / (pi R^2) (MPa)")
    left.legend(fontsize=7)
    right.set_title("error against cost")
    fig.tight_layout()
    out = args.out or os.path.join(folder(args), "resistance_chart.png")
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command",
                        choices=["run", "sweep", "sebs", "convergence", "domain", "grading",
                                 "resistance", "resistance-chart", "calibrate"])
    parser.add_argument("--case", choices=sorted(CASES), default="gelatin")
    parser.add_argument("--d", type=float, nargs="+", help="sphere diameters, m")
    parser.add_argument("--v0", type=float, nargs="+", help="impact velocities, m/s")
    parser.add_argument("--n", type=float, nargs="+", help="d / dx (default 10; convergence: "
                        "6 8 10 12 16; resistance: 8 16 32)")
    parser.add_argument("--set", action="append", default=[], help="extra case override")
    parser.add_argument("--results", default=os.path.join(ROOT, "results"))
    parser.add_argument("--tables", nargs="+", help="resistance-chart: resistance CSV tables")
    parser.add_argument("--labels", nargs="+", help="resistance-chart: one label per table")
    parser.add_argument("--limit", type=float, help="resistance-chart: the limit, MPa")
    parser.add_argument("--out", help="resistance-chart: the PNG (default under --results)")
    parser.add_argument("--travel", type=float, default=5.0,
                        help="resistance: the sphere's travel in diameters (default 5); the "
                        "resistance is the mean over its second half")
    parser.add_argument("--parameter", help="calibrate: the case key fitted, e.g. "
                        "materials.gelatin_10wt.youngs_modulus")
    parser.add_argument("--bracket", type=float, nargs=2, help="calibrate: its bounds")
    parser.add_argument("--tolerance", type=float, default=0.01,
                        help="calibrate: the search stops within this of log(parameter)")
    args = parser.parse_args()
    if not args.n:
        args.n = {"convergence": [6, 8, 10, 12, 16],
                  "resistance": [8, 16, 32]}.get(args.command, [10])
    {"run": cmd_run, "sweep": cmd_sweep, "sebs": cmd_sebs, "convergence": cmd_convergence,
     "domain": cmd_domain, "grading": cmd_grading,
     "resistance": cmd_resistance, "resistance-chart": cmd_resistance_chart,
     "calibrate": cmd_calibrate}[args.command](args)


if __name__ == "__main__":
    main()
