#!/usr/bin/env python3
"""Lumped, consistent and truncated-series (FMPM(k)) mass with linear,
quadratic and cubic B-splines on Tielen's vibrating bar (1D).

The bar of Tielen, Wobbes, Moeller, Beuth, "A high order material point
method", Procedia Engineering 175 (2017) 265: E = 100, rho = 1, L = 25,
both ends fixed, the first mode v(x, 0) = v0 sin(pi x / L), period
T = 2 L / c = 5. After one period the exact displacement is zero and the
velocity v0 sin(pi x / L) again; the error is the points' phase-space
error (||omega u_p(T)||^2 + ||V_p(T) - v(x_p, T)||^2)^(1/2), volume
weighted, relative to ||v(x_p, 0)|| (a phase error delta gives delta, a
motion damped out gives 1).

The bases are those of fmpm's B-spline layer (include/fmpm/bspline.h):
one function per vertex, knots at the vertices (p = 1, 3) or the cell
midpoints (p = 2), open knot vectors at both ends (the wall vertex's
function is 1 on the wall, the only one there: the fixed ends are
v = 0 on vertices 0 and n), the end's extra B-spline split between the two
vertices around its Greville abscissa.

The MPM step is linearised (the points stay at their initial positions:
the limit v0 -> 0, no geometric nonlinearity; the study isolates the
spatial and mass-matrix errors), with the stress updated last from the
grid velocity v+ (USL-). Per step, with p = S^T M V and f = -G^T (V_p s):

* lumped / consistent: FLIP, v+ = m^-1 (p + dt f), V += dt S m^-1 f,
  u += dt S v+, with the lumped mass or the consistent mass
  S^T M S (exact for points on Gauss points); Nairn's notes [Nairn2023-FMPM]
  Eq. 2.27 - 2.28 with psi = 0;
* FMPM(k): v+ = m~_k^-1 (p + dt f) with the k-term series
  (Nairn Eqs. 1.12 - 1.23), V = S v+, u += dt (V_old + V_new) / 2
  (Table 2.1); FMPM(exact): the full mass solved.

--series-check compares the series with the full mass for both updates
(FLIP with the series: V += dt S m~_k^-1 f).

Velocities are fixed to zero on the two end vertices (the mass matrices
restricted to the free vertices).

Since the stresses start at zero they stay s_p = E (G q)_p for a grid
displacement q, and V_p = c V0_p + (S w)_p, u_p = d V0_p + (S r)_p: the
step is a linear map of (c, d, w, q, r), 2 + 3 (n - 1) numbers. One
period is that map to the power N, by repeated squaring of I + D
(D_{2k} = 2 D_k + D_k^2: the increments keep their digits at tiny steps).

Two time steps: a tiny one, dt = T / 2^23 for every n (Courant number
c dt / h = 3.1e-5 at n = 128; the time error after one period is below
the round-off floor of a few 1e-11 (shaded in the charts; the orders
leave such errors out), first-order offsets cancel over a full period),
and Courant 0.2.

Output (default doc/studies/bspline_mass_1d/): results.csv,
orders.csv, error_tiny_step.png, error_courant_0.2.png.
Run time: about 10 s.
"""

import argparse
import csv
import math
import os
import sys

try:
    import numpy as np
except ImportError:  # pyenv Python without numpy: try Debian's packages
    _DEBIAN = "/usr/lib/python3/dist-packages"
    if os.path.isdir(_DEBIAN) and _DEBIAN not in sys.path:
        sys.path.append(_DEBIAN)
    import numpy as np  # noqa: E402

E, RHO, LENGTH = 100.0, 1.0, 25.0
WAVE_SPEED = math.sqrt(E / RHO)
OMEGA = math.pi * WAVE_SPEED / LENGTH
PERIOD = 2 * math.pi / OMEGA

CELLS = (8, 16, 32, 64, 128)
DEGREES = (1, 2, 3)
PLACEMENTS = ("gauss", "uniform")
METHODS = (("lumped", 0), ("consistent", 0), ("fmpm", 1), ("fmpm", 2),
           ("fmpm", 4), ("fmpm", 8), ("fmpm", 16), ("fmpm exact", 0))
TINY_STEPS = 2 ** 23
# Errors below this are round-off (the cubic consistent mass reaches it).
ROUND_OFF_FLOOR = 5e-11


def method_label(method, k):
    if method == "fmpm":
        return f"FMPM({k})"
    return {"lumped": "lumped (FLIP)", "consistent": "consistent (FLIP)",
            "fmpm exact": "FMPM(exact)"}[method]


# ---------------------------------------------------------------------------
# The basis (include/fmpm/bspline.h, open knots)
# ---------------------------------------------------------------------------

def knot(m, p, n):
    """Knot m in cells, open at both ends."""
    return min(max(m - 0.5 * (p + 1), 0.0), float(n))


def vertex_values(t, p, n):
    """S_i(t) and dS_i/dt of the vertices i = 0 ... n at t in [0, n]."""
    shift = 0.5 * (p + 1)
    j = min(max(int(math.floor(t + shift)), int(math.floor(shift))),
            int(math.ceil(n + shift)) - 1)
    u = lambda m: knot(m, p, n)  # noqa: E731
    N = [1.0]
    previous = N
    for q in range(1, p + 1):
        previous = N
        N = []
        for r in range(q + 1):
            m = j - q + r
            value = 0.0
            if r >= 1:
                value += (t - u(m)) / (u(m + q) - u(m)) * previous[r - 1]
            if r + 1 <= q:
                value += ((u(m + q + 1) - t) / (u(m + q + 1) - u(m + 1))
                          * previous[r])
            N.append(value)
    dN = []
    for r in range(p + 1):
        m = j - p + r
        d = 0.0
        if r >= 1:
            d += previous[r - 1] / (u(m + p) - u(m))
        if r + 1 <= p:
            d -= previous[r] / (u(m + p + 1) - u(m + 1))
        dN.append(p * d)
    S = np.zeros(n + 1)
    dS = np.zeros(n + 1)
    for r in range(p + 1):
        m = j - p + r
        g = sum(u(m + k) for k in range(1, p + 1)) / p
        i = int(math.floor(g))
        f = g - i
        S[i] += (1 - f) * N[r]
        dS[i] += (1 - f) * dN[r]
        if f != 0:
            S[i + 1] += f * N[r]
            dS[i + 1] += f * dN[r]
    return S, dS


def points(p, n, placement):
    """Positions (in cells) and volume fractions (of a cell) of the points:
    p + 1 Gauss points on each knot span, or p + 1 evenly spaced points
    per cell (centres of equal sub-cells)."""
    if placement == "uniform":
        k = p + 1
        t = np.array([i + (a + 0.5) / k for i in range(n) for a in range(k)])
        return t, np.full(t.size, 1.0 / k)
    xg, wg = np.polynomial.legendre.leggauss(p + 1)
    breaks = sorted({knot(m, p, n) for m in range(-p - 2, n + p + 3)})
    t, w = [], []
    for a, b in zip(breaks[:-1], breaks[1:]):
        t.extend(0.5 * (a + b) + 0.5 * (b - a) * xg)
        w.extend(0.5 * (b - a) * wg)
    return np.array(t), np.array(w)


# ---------------------------------------------------------------------------
# The linearised MPM step and one period
# ---------------------------------------------------------------------------

def operators(p, n, placement):
    h = LENGTH / n
    t, fraction = points(p, n, placement)
    volume = fraction * h
    S = np.array([vertex_values(s, p, n)[0] for s in t])
    G = np.array([vertex_values(s, p, n)[1] for s in t]) / h
    x = t * h
    free = slice(1, n)  # vertices 0 and n fixed
    return x, volume, S[:, free], G[:, free]


def inverse_mass(method, k, S, mass):
    lumped = S.T @ mass
    full = S.T @ (mass[:, None] * S)
    lumped_inverse = np.diag(1.0 / lumped)
    if method == "lumped":
        return lumped_inverse
    if method in ("consistent", "fmpm exact"):
        return np.linalg.inv(full)
    # FMPM(k) and "flip series" (FLIP with the series: a = m~_k^-1 f)
    # k-term series (Nairn Eq. 1.12): sum_{l<k} (I - m^-1 m~)^l m^-1
    A = np.eye(lumped.size) - lumped_inverse @ full
    result = np.zeros_like(A)
    power = np.eye(lumped.size)
    for _ in range(k):
        result += power
        power = power @ A
    return result @ lumped_inverse


def step_increment(method, k, S, G, volume, V0, dt):
    """D = T - I for the state (c, d, w, q, r)."""
    mass = RHO * volume
    nf = S.shape[1]
    Minv = inverse_mass(method, k, S, mass)
    b = S.T @ (mass * V0)                     # p = c b + m~ w
    full = S.T @ (mass[:, None] * S)
    K = E * (G.T @ (volume[:, None] * G))     # f = -K q
    size = 2 + 3 * nf
    ic, id_ = 0, 1
    iw = slice(2, 2 + nf)
    iq = slice(2 + nf, 2 + 2 * nf)
    ir = slice(2 + 2 * nf, 2 + 3 * nf)
    T = np.zeros((size, size))
    # v+ = Minv (c b + m~ w - dt K q) as rows over the state
    vplus = np.zeros((nf, size))
    vplus[:, ic] = Minv @ b
    vplus[:, iw] = Minv @ full
    vplus[:, iq] = -dt * (Minv @ K)
    # q' = q + dt v+
    T[iq, :] = dt * vplus
    T[iq, iq] += np.eye(nf)
    if method in ("lumped", "consistent", "flip series"):
        # V' = V + dt S Minv f: c' = c, w' = w - dt^2 ... (f = -K q)
        T[ic, ic] = 1
        T[iw, iw] = np.eye(nf)
        T[iw, iq] = -dt * (Minv @ K)
        # u' = u + dt S v+: d' = d, r' = r + dt v+
        T[id_, id_] = 1
        T[ir, :] = dt * vplus
        T[ir, ir] += np.eye(nf)
    else:
        # V' = S v+: c' = 0, w' = v+; u' = u + dt (V + V')/2
        T[iw, :] = vplus
        T[id_, id_] = 1
        T[id_, ic] = 0.5 * dt
        T[ir, :] = 0.5 * dt * vplus
        T[ir, iw] += 0.5 * dt * np.eye(nf)
        T[ir, ir] += np.eye(nf)
    return T - np.eye(size)


def power_of_identity_plus(D, N):
    """(I + D)^N - I by repeated squaring of I + D."""
    result = np.zeros_like(D)        # (I + R) accumulated
    base = D.copy()
    while N > 0:
        if N & 1:
            result = result + base + result @ base
        N >>= 1
        if N:
            base = 2 * base + base @ base
    return result


def error_after_one_period(p, n, placement, method, k, steps):
    x, volume, S, G = operators(p, n, placement)
    V0 = np.sin(math.pi * x / LENGTH)                  # v0 = 1
    dt = PERIOD / steps
    D = step_increment(method, k, S, G, volume, V0, dt)
    z0 = np.zeros(D.shape[0])
    z0[0] = 1.0
    z = z0 + power_of_identity_plus(D, steps) @ z0
    nf = S.shape[1]
    V = z[0] * V0 + S @ z[2:2 + nf]
    u = z[1] * V0 + S @ z[2 + 2 * nf:]
    # The phase-space error against u(T) = 0, v(T) = V0 (v0 = 1).
    error = math.sqrt(np.sum(volume * ((OMEGA * u) ** 2 + (V - V0) ** 2)) /
                      np.sum(volume * V0 * V0))
    return error if math.isfinite(error) else float("inf")


# ---------------------------------------------------------------------------
# Study
# ---------------------------------------------------------------------------

def run(output):
    rows = []
    for label, courant in (("tiny", None), ("0.2", 0.2)):
        for placement in PLACEMENTS:
            for p in DEGREES:
                for method, k in METHODS:
                    for n in CELLS:
                        h = LENGTH / n
                        steps = (TINY_STEPS if courant is None else
                                 int(math.ceil(PERIOD * WAVE_SPEED /
                                               (courant * h) - 1e-9)))
                        error = error_after_one_period(p, n, placement,
                                                       method, k, steps)
                        rows.append(dict(step=label, placement=placement,
                                         degree=p,
                                         method=method_label(method, k),
                                         cells=n, steps=steps,
                                         courant=WAVE_SPEED * PERIOD
                                         / steps / h,
                                         error=error))
    with open(os.path.join(output, "results.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({**row, "courant": f"{row['courant']:.4g}",
                             "error": f"{row['error']:.6e}"})
    return rows


def orders(rows):
    """Least-squares slope of log error against log n over 8 ... 128 and
    the slope of the last halving, skipping errors above 0.5 (no
    convergence) or below the round-off floor."""
    out = []
    keys = sorted({(r["step"], r["placement"], r["degree"], r["method"])
                   for r in rows}, key=str)
    for key in keys:
        series = [(r["cells"], r["error"]) for r in rows
                  if (r["step"], r["placement"], r["degree"],
                      r["method"]) == key]
        series.sort()
        good = [(n, e) for n, e in series if ROUND_OFF_FLOOR < e < 0.5]
        if len(good) < 2:
            fit = last = float("nan")
        else:
            X = np.log([n for n, _ in good])
            Y = np.log([e for _, e in good])
            fit = -np.polyfit(X, Y, 1)[0]
            last = -(Y[-1] - Y[-2]) / (X[-1] - X[-2])
        out.append(dict(step=key[0], placement=key[1], degree=key[2],
                        method=key[3], error_8=series[0][1],
                        error_16=series[1][1], error_128=series[-1][1],
                        order_fit=fit, order_last=last))
    return out


def chart(rows, step, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(PLACEMENTS), len(DEGREES),
                             figsize=(14, 8.5), sharex=True, sharey=True)
    styles = {"lumped (FLIP)": ("k", "o", "-"),
              "consistent (FLIP)": ("tab:red", "s", "-"),
              "FMPM(exact)": ("tab:blue", "D", "-"),
              "FMPM(1)": ("0.75", "v", "--"),
              "FMPM(2)": ("tab:olive", "v", "--"),
              "FMPM(4)": ("tab:orange", "^", "--"),
              "FMPM(8)": ("tab:purple", "<", "--"),
              "FMPM(16)": ("tab:cyan", ">", "--")}
    for a, placement in enumerate(PLACEMENTS):
        for b, p in enumerate(DEGREES):
            ax = axes[a][b]
            for method, k in METHODS:
                label = method_label(method, k)
                data = sorted((r["cells"], r["error"]) for r in rows
                              if r["step"] == step
                              and r["placement"] == placement
                              and r["degree"] == p and r["method"] == label)
                n = [d[0] for d in data]
                e = [min(d[1], 10.0) for d in data]
                color, marker, line = styles[label]
                ax.loglog(n, e, color=color, marker=marker, linestyle=line,
                          label=label, markersize=4)
            ax.axhspan(1e-13, ROUND_OFF_FLOOR, color="0.95")
            for order, anchor in ((2, 0.5), (3, 0.05), (4, 0.005),
                                  (6, 5e-6)):
                ax.loglog([8, 128], [anchor, anchor * 16.0 ** -order],
                          color="0.85", linewidth=0.8)
                ax.text(128, anchor * 16.0 ** -order, f" {order}",
                        color="0.6", fontsize=7, va="center")
            name = {1: "linear", 2: "quadratic", 3: "cubic"}[p]
            ax.set_title(f"{name} B-splines, points "
                         f"{'on Gauss points' if placement == 'gauss' else 'evenly spaced'}",
                         fontsize=9)
            ax.set_xticks(CELLS)
            ax.set_xticklabels([str(c) for c in CELLS])
            ax.grid(True, which="major", color="0.92")
            if b == 0:
                ax.set_ylabel("phase-space error after one period")
            if a == len(PLACEMENTS) - 1:
                ax.set_xlabel("cells")
    axes[0][0].set_ylim(1e-13, 20)
    axes[0][0].legend(fontsize=7, loc="lower left")
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def series_check():
    """Whether the k-term series reaches the full mass at the tiny step
    with either update: FMPM(k) against FMPM(exact), and FLIP with the
    series (a = m~_k^-1 f) against FLIP with the consistent mass;
    quadratic basis, Gauss points. Prints the ratios."""
    steps = 2 ** 23
    for n in (8, 16, 32):
        exact = error_after_one_period(2, n, "gauss", "fmpm exact", 0, steps)
        consistent = error_after_one_period(2, n, "gauss", "consistent", 0,
                                            steps)
        for k in (2, 4, 8, 16):
            fmpm = error_after_one_period(2, n, "gauss", "fmpm", k, steps)
            flip = error_after_one_period(2, n, "gauss", "flip series", k,
                                          steps)
            print(f"n = {n:3} k = {k:2}: FMPM(k) {fmpm:.3e} = "
                  f"{fmpm / exact:9.3g} x FMPM(exact); FLIP with the series "
                  f"{flip:.3e} = {flip / consistent:8.3g} x consistent FLIP",
                  flush=True)


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    default = os.path.normpath(os.path.join(here, "..", "..", "..", "doc",
                                            "studies", "bspline_mass_1d"))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--output", default=default)
    parser.add_argument("--no-charts", action="store_true")
    parser.add_argument("--series-check", action="store_true",
                        help="only compare the truncated series with the "
                        "full mass at the tiny step, for both updates")
    args = parser.parse_args(argv)
    if args.series_check:
        series_check()
        return
    os.makedirs(args.output, exist_ok=True)
    rows = run(args.output)
    table = orders(rows)
    with open(os.path.join(args.output, "orders.csv"), "w",
              newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(table[0]))
        writer.writeheader()
        for row in table:
            writer.writerow({k: (f"{v:.3g}" if isinstance(v, float) else v)
                             for k, v in row.items()})
    for row in table:
        print(f"{row['step']:5} {row['placement']:8} p={row['degree']} "
              f"{row['method']:18} e(8)={row['error_8']:.2e} "
              f"e(128)={row['error_128']:.2e} order {row['order_fit']:.2f} "
              f"(last {row['order_last']:.2f})")
    if not args.no_charts:
        chart(rows, "tiny", os.path.join(args.output, "error_tiny_step.png"),
              "Tielen's bar after one period, dt = T/2^23: "
              "mass matrices with B-splines (linearised MPM, USL-)")
        chart(rows, "0.2", os.path.join(args.output,
                                        "error_courant_0.2.png"),
              "Tielen's bar after one period, Courant number 0.2")


if __name__ == "__main__":
    main()
