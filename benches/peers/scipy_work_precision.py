#!/usr/bin/env python3
"""Work-precision runs of scipy's solve_ivp on tumble's reference problems (not part of CI).

    python benches/peers/scipy_work_precision.py --out DIR [--problem NAME]... [--budget SECONDS]

Writes DIR/scipy_work_precision.csv with the columns of tumble's work_precision tool
(problem,method,param,error,seconds,rhs_evals,steps,rejected), methods named scipy-RK45, scipy-DOP853, scipy-Radau,
scipy-BDF, scipy-LSODA. The same tolerances as tumble (rtol = tol, atol = tol x the problem's atol scale), the same
error norms and reference values. Implicit methods get the analytic Jacobian, as tumble's Rodas4 does. Explicit
methods are not run on the stiff problems. solve_ivp does not report rejected steps: that column is left empty.

Then overlay and compare:
    cargo run --release -p tumble-integrate --example work_precision -- --out DIR --peer DIR/scipy_work_precision.csv
"""
import argparse
import math
import os
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp


def lotka(t, u):
    a, b, c, d = 1.5, 1.0, 3.0, 1.0
    return np.array([a * u[0] - b * u[0] * u[1], -c * u[1] + d * u[0] * u[1]])


def lotka_jac(t, u):
    a, b, c, d = 1.5, 1.0, 3.0, 1.0
    return np.array([[a - b * u[1], -b * u[0]], [d * u[1], -c + d * u[0]]])


MU = 0.012277471


def arenstorf(t, u):
    mu1 = 1.0 - MU
    x, y = u[0], u[1]
    d1 = ((x + MU) ** 2 + y * y) ** 1.5
    d2 = ((x - mu1) ** 2 + y * y) ** 1.5
    return np.array([u[2], u[3], x + 2 * u[3] - mu1 * (x + MU) / d1 - MU * (x - mu1) / d2,
                     y - 2 * u[2] - mu1 * y / d1 - MU * y / d2])


def kepler(t, y):
    r3 = (y[0] ** 2 + y[1] ** 2) ** 1.5
    return np.array([y[2], y[3], -y[0] / r3, -y[1] / r3])


def kepler_jac(t, y):
    x, z = y[0], y[1]
    r2 = x * x + z * z
    r3, r5 = r2 ** 1.5, r2 ** 2.5
    return np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                     [-1 / r3 + 3 * x * x / r5, 3 * x * z / r5, 0, 0],
                     [3 * x * z / r5, -1 / r3 + 3 * z * z / r5, 0, 0]])


EPS = 1e-6


def vdp(t, y):
    return np.array([y[1], ((1 - y[0] ** 2) * y[1] - y[0]) / EPS])


def vdp_jac(t, y):
    return np.array([[0.0, 1.0], [(-2 * y[0] * y[1] - 1) / EPS, (1 - y[0] ** 2) / EPS]])


def rober(t, y):
    a = -0.04 * y[0] + 1e4 * y[1] * y[2]
    c = 3e7 * y[1] ** 2
    return np.array([a, -a - c, c])


def rober_jac(t, y):
    return np.array([[-0.04, 1e4 * y[2], 1e4 * y[1]],
                     [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
                     [0.0, 6e7 * y[1], 0.0]])


def hires(t, y):
    return np.array([
        -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007,
        1.71 * y[0] - 8.75 * y[1],
        -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4],
        8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3],
        -1.745 * y[4] + 0.43 * y[5] + 0.43 * y[6],
        -280 * y[5] * y[7] + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6],
        280 * y[5] * y[7] - 1.81 * y[6],
        -280 * y[5] * y[7] + 1.81 * y[6]])


def hires_jac(t, y):
    j = np.zeros((8, 8))
    j[0, :3] = [-1.71, 0.43, 8.32]
    j[1, :2] = [1.71, -8.75]
    j[2, 2:5] = [-10.03, 0.43, 0.035]
    j[3, 1:4] = [8.32, 1.71, -1.12]
    j[4, 4:7] = [-1.745, 0.43, 0.43]
    j[5, 3:8] = [0.69, 1.71, -280 * y[7] - 0.43, 0.69, -280 * y[5]]
    j[6, 5:8] = [280 * y[7], -1.81, 280 * y[5]]
    j[7, 5:8] = [-280 * y[7], 1.81, -280 * y[5]]
    return j


def orego(t, y):
    return np.array([77.27 * (y[1] + y[0] * (1 - 8.375e-6 * y[0] - y[1])),
                     (y[2] - (1 + y[0]) * y[1]) / 77.27,
                     0.161 * (y[0] - y[2])])


def orego_jac(t, y):
    return np.array([[77.27 * (1 - 2 * 8.375e-6 * y[0] - y[1]), 77.27 * (1 - y[0]), 0],
                     [-y[1] / 77.27, -(1 + y[0]) / 77.27, 1 / 77.27],
                     [0.161, 0, -0.161]])


def spring(t, y):
    return np.array([y[1], -1e8 * y[0]])


def spring_jac(t, y):
    return np.array([[0.0, 1.0], [-1e8, 0.0]])


W = 1e4
# name: (f, jac, y0, t_end, reference, stiff, norm, atol_scale), as in tumble_integrate::problems.
PROBLEMS = {
    "lotka-volterra": (lotka, lotka_jac, [1.0, 1.0], 10.0, None, False, "relative", 1.0),
    "arenstorf": (arenstorf, None, [0.994, 0.0, 0.0, -2.00158510637908252240537862224], 17.0652165601579625588917206249,
                  [0.994, 0.0, 0.0, -2.00158510637908252240537862224], False, "relative", 1.0),
    "kepler": (kepler, kepler_jac, [0.4, 0.0, 0.0, 2.0], 2 * math.pi, [0.4, 0.0, 0.0, 2.0], False, "relative", 1.0),
    "van-der-pol": (vdp, vdp_jac, [2.0, 0.0], 2.0, [1.706167732170483, -0.8928097010247975], True, "componentwise", 1.0),
    "rober": (rober, rober_jac, [1.0, 0.0, 0.0], 1e11,
              [0.2083340149701255e-7, 0.8333360770334713e-13, 0.9999999791665050], True, "componentwise", 1e-10),
    "hires": (hires, hires_jac, [1, 0, 0, 0, 0, 0, 0, 0.0057], 321.8122,
              [0.7371312573325668e-3, 0.1442485726316185e-3, 0.5888729740967575e-4, 0.1175651343283149e-2,
               0.2386356198831331e-2, 0.6238968252742796e-2, 0.2849998395185769e-2, 0.2850001604814231e-2],
              True, "componentwise", 1e-4),
    "orego": (orego, orego_jac, [1.0, 2.0, 3.0], 360.0, [1.000814870318523, 1228.178521549917, 132.0554942846706],
              True, "componentwise", 1.0),
    "stiff-spring": (spring, spring_jac, [1.0, 0.0], 0.01, [math.cos(W * 0.01), -W * math.sin(W * 0.01)], False,
                     "relative", 1.0),
}
TOLERANCES = [10.0 ** -k for k in range(3, 12)]


def error(y, ref, norm):
    y, ref = np.asarray(y), np.asarray(ref)
    if norm == "relative":
        return float(np.linalg.norm(y - ref) / np.linalg.norm(ref))
    return float(np.max(np.abs(y - ref) / np.abs(ref)))


def solve(name, method, rtol, atol):
    f, jac, y0, t_end, _, _, _, _ = PROBLEMS[name]
    kw = {"jac": jac} if method in ("Radau", "BDF", "LSODA") and jac is not None else {}
    return solve_ivp(f, (0.0, t_end), y0, method=method, rtol=rtol, atol=atol, **kw)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--problem", action="append", choices=list(PROBLEMS))
    ap.add_argument("--budget", type=float, default=0.3, help="timing budget per point in seconds")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name in args.problem or list(PROBLEMS):
        f, jac, y0, t_end, ref, stiff, norm, atol_scale = PROBLEMS[name]
        if ref is None:
            ref = solve(name, "DOP853", 1e-14, 1e-14).y[:, -1]
        methods = ["Radau", "BDF", "LSODA"] if stiff else ["RK45", "DOP853", "Radau", "BDF", "LSODA"]
        for method in methods:
            for tol in TOLERANCES:
                start = time.perf_counter()
                sol = solve(name, method, tol, tol * atol_scale)
                first = time.perf_counter() - start
                if not sol.success:
                    print(f"{name} {method} {tol:.0e}: {sol.message}", file=sys.stderr)
                    continue
                err = error(sol.y[:, -1], ref, norm)
                best = first
                for _ in range(max(2, min(10, int(args.budget / max(first, 1e-9))))):
                    start = time.perf_counter()
                    solve(name, method, tol, tol * atol_scale)
                    best = min(best, time.perf_counter() - start)
                if err <= 1.0:
                    rows.append(f"{name},scipy-{method},{tol:e},{err:e},{best:e},{sol.nfev},{len(sol.t) - 1},")
                print(f"{name:15} {method:6} tol {tol:.0e} error {err:.2e} {best * 1e3:9.2f} ms", file=sys.stderr)
    path = os.path.join(args.out, "scipy_work_precision.csv")
    with open(path, "w") as fh:
        fh.write("problem,method,param,error,seconds,rhs_evals,steps,rejected\n")
        fh.write("\n".join(rows) + "\n")
    print(f"wrote {path} ({len(rows)} points)")


if __name__ == "__main__":
    main()
