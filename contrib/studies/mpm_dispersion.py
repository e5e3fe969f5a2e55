#!/usr/bin/env python3
"""Linear (von Neumann / Bloch-wave) analysis of fmpm's time step.

Two kinds of prediction for the vibrating bar and the stability study:

* the textbook **finite element dispersion relations** of a uniform 1D grid
  of linear elements with central differences (leapfrog):

  - lumped mass:     sin(w dt/2) = nu sin(theta/2)
  - consistent mass: the same with the mass (2 + cos theta)/3
  - FMPM(k):         the mass replaced by the k-term series of its inverse

  giving the critical Courant numbers nu = c dt / h (1 lumped, 0.775 for
  FMPM(2), 0.61 for FMPM(5), 1/sqrt(3) consistent) and the relative
  frequency errors -theta^2 (1 - nu^2)/24 (lumped) and
  +theta^2 (1 + nu^2)/24 (consistent), theta = k h the wave number times
  the cell size (theta = pi h / (2 L) for the bar's first mode);

* the **MPM step of fmpm itself**, linearised (points at their initial
  positions, small strains): the particle-to-grid matrix S of the points at
  the centres of a regular subdivision of each cell (Points per cell), the
  lumped / FMPM(k) / full / consistent mass matrices built from them, the
  strain update (USF, USL-, USL+, USAVG, USAVG+) and the particle update
  (flip, pic, fmpm, xpic, flip pic blend) exactly as in
  source/simulator/core.cc and source/particle_update/.  The step is a
  linear map of the point velocities and stresses; on a periodic grid its
  eigenvalues for a Bloch wave exp(i theta x/h) give the stability limit
  (spectral radius > 1) and the frequency and damping of a mode.  Two
  geometries: ``1d`` (a line of cells) and ``strip`` (the vibrating bar's
  2D strip one cell high with roller walls, Poisson's ratio 0: only x
  velocities, stresses sigma_xx and sigma_xy; this adds modes that vary
  across the strip).  In 1D the shape functions may also be fmpm's
  quadratic or cubic B-splines (``b2spline``, support +-1.5 cells, knots at
  the cell centres; ``b3spline``, +-2 cells, knots at the vertices), the
  interior basis of a uniform grid: the cardinal B-splines centred on the
  vertices.

Run ``mpm_dispersion.py`` to print a table of critical Courant numbers.
Needs numpy (Debian: python3-numpy; the script falls back to
/usr/lib/python3/dist-packages like fmpm_study.py).
"""

import argparse
import cmath
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

STRAIN_UPDATES = ("usf", "usl", "usl+", "usavg", "usavg+")
PARTICLE_UPDATES = ("flip", "pic", "fmpm", "xpic", "flip pic blend")
MASS_MATRICES = ("lumped", "fmpm", "full", "consistent")
SHAPES = ("linear", "b2spline", "b3spline")


def cardinal_bspline(x, degree):
    """(N(x), N'(x)) of the centred cardinal B-spline of the degree
    (1: the hat, 2: support |x| < 3/2, 3: support |x| < 2), h = 1."""
    a = abs(x)
    sign = 1.0 if x >= 0 else -1.0
    if degree == 1:
        return (1 - a, -sign) if a < 1 else (0.0, 0.0)
    if degree == 2:
        if a < 0.5:
            return 0.75 - a * a, -2 * x
        if a < 1.5:
            return 0.5 * (1.5 - a) ** 2, -sign * (1.5 - a)
        return 0.0, 0.0
    if degree == 3:
        if a < 1:
            return 2 / 3 - a * a + 0.5 * a ** 3, sign * (-2 * a + 1.5 * a * a)
        if a < 2:
            return (2 - a) ** 3 / 6, -sign * 0.5 * (2 - a) ** 2
        return 0.0, 0.0
    raise ValueError(f"unknown degree {degree}")


def shape_degree(shape):
    try:
        return SHAPES.index(shape) + 1
    except ValueError:
        raise ValueError(f"unknown shape '{shape}' (allowed: "
                         f"{', '.join(SHAPES)})") from None


def bspline_mass_symbol(theta, degree, rho=1.0, h=1.0):
    """Exact integral of rho N_0 N_j over the line, Bloch reduced:
    sum_j exp(i theta j) int N(x) N(x - j) dx (Gauss quadrature per knot
    span, exact for the piecewise polynomial)."""
    nodes, weights = np.polynomial.legendre.leggauss(degree + 1)
    half = 0.5 * (degree + 1)
    knots = np.arange(-half, half + 1e-12, 1.0)
    total = 0j
    for j in range(-degree, degree + 1):
        integral = 0.0
        for left, right in zip(knots[:-1], knots[1:]):
            for xi, w in zip(nodes, weights):
                x = 0.5 * (left + right) + 0.5 * (right - left) * xi
                integral += 0.5 * (right - left) * w * (
                    cardinal_bspline(x, degree)[0]
                    * cardinal_bspline(x - j, degree)[0])
        total += cmath.exp(1j * theta * j) * integral
    return rho * h * total


# ---------------------------------------------------------------------------
# Textbook finite element dispersion (uniform 1D grid, leapfrog)
# ---------------------------------------------------------------------------

def fe_inverse_mass_factor(theta, mass, order=1):
    """Eigenvalue of (mass matrix)^-1 times the lumped mass for the Fourier
    mode theta of a uniform 1D grid of linear elements (exact integrals).

    mass: 'lumped' (1), 'consistent' (3/(2 + cos theta)), 'fmpm' (k-term
    series sum_{j<k} (1 - r)^j, r = (2 + cos theta)/3).
    """
    r = (2.0 + math.cos(theta)) / 3.0
    if mass == "lumped" or (mass == "fmpm" and order == 1):
        return 1.0
    if mass in ("consistent", "full"):
        return 1.0 / r
    if mass == "fmpm":
        return sum((1.0 - r) ** j for j in range(order))
    raise ValueError(f"unknown mass matrix '{mass}'")


def fe_critical_courant(mass, order=1):
    """Largest nu = c dt/h for which leapfrog with this mass is stable:
    nu^2 * 4 sin^2(theta/2) * factor(theta) <= 4 for all theta."""
    worst = max(math.sin(t / 2) ** 2 * fe_inverse_mass_factor(t, mass, order)
                for t in np.linspace(0, math.pi, 2001))
    return 1.0 / math.sqrt(worst)


def fe_frequency_error(theta, nu, mass, order=1):
    """Relative frequency error (omega_h - omega)/omega of the mode theta
    (= k h) with leapfrog at Courant number nu, exact (not expanded)."""
    if theta == 0:
        return 0.0
    s = nu * math.sin(theta / 2) * math.sqrt(
        fe_inverse_mass_factor(theta, mass, order))
    if s >= 1:
        return float("nan")
    return 2 * math.asin(s) / (nu * theta) - 1


def fe_frequency_error_leading(theta, nu, mass):
    """Leading terms: -theta^2 (1-nu^2)/24 (lumped),
    +theta^2 (1+nu^2)/24 (consistent)."""
    if mass == "lumped":
        return -theta ** 2 * (1 - nu ** 2) / 24
    return theta ** 2 * (1 + nu ** 2) / 24


# ---------------------------------------------------------------------------
# Linearised MPM step of fmpm on a periodic grid (Bloch waves)
# ---------------------------------------------------------------------------

class Cell:
    """Bloch-reduced operators of one periodic cell (column).

    Degrees of freedom: the x velocity of the node(s) at the cell's left
    edge (1 in 1D; bottom and top in the strip).  Points at the centres of
    a regular ppc (x ppc) subdivision.  Bloch phase exp(i theta) per cell.
    """

    def __init__(self, theta, geometry="1d", ppc=2, h=1.0, rho=1.0,
                 modulus=100.0, shear=50.0, shape="linear"):
        self.geometry = geometry
        degree = shape_degree(shape)
        if degree > 1 and geometry != "1d":
            raise ValueError("B-splines are modelled in 1D only")
        xi = [(q + 0.5) / ppc for q in range(ppc)]
        phase = cmath.exp(1j * theta)
        points = []  # (shape row, d/dx row, d/dy row)
        if geometry == "1d" and degree > 1:
            # Row of a point at a (cell units from the cell's left vertex):
            # sum over the vertices j it reaches of N(a - j) exp(i theta j).
            volume = h / ppc
            reach = range(-degree, degree + 2)
            for a in xi:
                values = [cardinal_bspline(a - j, degree) for j in reach]
                points.append((
                    [sum(v[0] * phase ** j for v, j in zip(values, reach))],
                    [sum(v[1] * phase ** j for v, j in zip(values, reach))
                     / h], None))
        elif geometry == "1d":
            volume = h / ppc
            for a in xi:
                points.append(([(1 - a) + a * phase],
                               [(-1 + phase) / h], None))
        elif geometry == "strip":
            volume = h * h / ppc ** 2
            for a in xi:
                nx = (1 - a) + a * phase
                dnx = (-1 + phase) / h
                for b in xi:
                    points.append(([nx * (1 - b), nx * b],
                                   [dnx * (1 - b), dnx * b],
                                   [-nx / h, nx / h]))
        else:
            raise ValueError(f"unknown geometry '{geometry}'")
        self.S = np.array([p[0] for p in points], dtype=complex)
        self.Gx = np.array([p[1] for p in points], dtype=complex)
        self.Gy = (np.array([p[2] for p in points], dtype=complex)
                   if geometry == "strip" else None)
        self.n_points, self.n_dofs = self.S.shape
        self.mass = rho * volume          # per point
        self.volume = volume
        self.modulus = modulus            # lambda + 2 mu (sigma_xx)
        self.shear = shear                # mu (sigma_xy)
        self.full = self.mass * (self.S.conj().T @ self.S)
        # Lumped: the real row sums S^T M 1 (every node gets sum N_i m_p).
        real = np.array([p[0] for p in self._real_rows(xi)])
        self.lumped = self.mass * real.sum(axis=0)
        self.consistent = (self._consistent(theta, h, rho) if degree == 1
                           else np.array([[bspline_mass_symbol(
                               theta, degree, rho, h)]]))

    def _real_rows(self, xi):
        """Shape function rows of the points with theta = 0 summed over the
        two cells a node touches (for the lumped mass)."""
        rows = []
        if self.geometry == "1d":
            for _ in xi:
                rows.append(([1.0],))
        else:
            for _ in xi:
                for b in xi:
                    rows.append(([1 - b, b],))
        return rows

    def _consistent(self, theta, h, rho):
        """Exact integral of rho N_i N_j (Q1 elements), Bloch reduced."""
        mx = rho * h * (2.0 + math.cos(theta)) / 3.0
        if self.geometry == "1d":
            return np.array([[mx]], dtype=complex)
        my = h * np.array([[1 / 3, 1 / 6], [1 / 6, 1 / 3]])
        return mx * my.astype(complex)


def inverse_mass(cell, mass, order=1):
    """The matrix of v = m^-1 p for the named mass matrix."""
    lumped_inv = np.diag(1.0 / cell.lumped).astype(complex)
    if mass == "lumped" or (mass == "fmpm" and order <= 1):
        return lumped_inv
    if mass == "full":
        return np.linalg.inv(cell.full)
    if mass == "consistent":
        return np.linalg.inv(cell.consistent)
    if mass == "fmpm":
        # k Jacobi-Richardson sweeps on full v = p from v = 0.
        n = cell.n_dofs
        iteration = np.eye(n) - lumped_inv @ cell.full
        result = np.zeros((n, n), dtype=complex)
        power = np.eye(n, dtype=complex)
        for _ in range(order):
            result += power
            power = power @ iteration
        return result @ lumped_inv
    raise ValueError(f"unknown mass matrix '{mass}'")


def step_matrix(cell, nu, update="fmpm", mass="lumped", order=1,
                strain="usavg+", strain_mass="same", blend=0.95, c=10.0,
                h=1.0):
    """The linear map of one fmpm time step on the state
    z = (V, sigma_xx[, sigma_xy]) of the points of a Bloch cell."""
    dt = nu * h / c
    n = cell.n_points
    blocks = 3 if cell.Gy is not None else 2
    size = blocks * n
    S, Gx, Gy = cell.S, cell.Gx, cell.Gy
    SH = S.conj().T
    M = cell.mass
    Minv = inverse_mass(cell, mass, order)
    Linv = inverse_mass(cell, "lumped")
    Sinv = Linv if strain_mass == "lumped" else Minv
    first = strain in ("usf", "usavg", "usavg+")
    last = strain != "usf"
    re_extrapolate = strain in ("usl+", "usavg+")
    average = strain in ("usavg", "usavg+")

    def stress_update(sxx, sxy, v, tau):
        sxx = sxx + tau * cell.modulus * (Gx @ v)
        if Gy is not None:
            sxy = sxy + tau * cell.shear * (Gy @ v)
        return sxx, sxy

    def force(sxx, sxy):
        f = -cell.volume * (Gx.conj().T @ sxx)
        if Gy is not None:
            f = f - cell.volume * (Gy.conj().T @ sxy)
        return f

    def apply(z):
        V = z[:n]
        sxx = z[n:2 * n]
        sxy = z[2 * n:] if Gy is not None else None
        p = M * (SH @ V)
        if first:
            sxx, sxy = stress_update(sxx, sxy, Sinv @ p,
                                     dt / 2 if average else dt)
        f = force(sxx, sxy)
        pp = p + dt * f
        if update == "flip":
            V_new = V + dt * (S @ (Minv @ f))
        elif update in ("pic", "fmpm"):
            V_new = S @ (Minv @ pp)
        elif update == "xpic":
            V_new = S @ (Minv @ p) + dt * (S @ (Linv @ f))
        elif update == "flip pic blend":
            V_new = blend * V + S @ (Minv @ (pp - blend * p))
        else:
            raise ValueError(f"unknown particle update '{update}'")
        if last:
            tau = dt / 2 if average else dt
            if re_extrapolate:
                v = Sinv @ (M * (SH @ V_new))
            else:
                v = Sinv @ pp
            sxx, sxy = stress_update(sxx, sxy, v, tau)
        parts = [V_new, sxx] + ([sxy] if Gy is not None else [])
        return np.concatenate(parts)

    matrix = np.zeros((size, size), dtype=complex)
    for j in range(size):
        e = np.zeros(size, dtype=complex)
        e[j] = 1
        matrix[:, j] = apply(e)
    return matrix


def spectral_radius(nu, thetas=None, geometry="1d", ppc=2, shape="linear",
                    **scheme):
    """Largest |eigenvalue| of the step over the Bloch wave numbers."""
    if thetas is None:
        thetas = np.linspace(0, math.pi, 33)
    worst = 0.0
    for theta in thetas:
        cell = Cell(theta, geometry, ppc, shape=shape)
        eigenvalues = np.linalg.eigvals(step_matrix(cell, nu, **scheme))
        worst = max(worst, float(np.abs(eigenvalues).max()))
    return worst


def critical_courant(geometry="1d", ppc=2, low=0.05, high=3.0,
                     tolerance=1e-3, growth=1e-6, shape="linear", **scheme):
    """Largest Courant number with spectral radius <= 1 + growth, found by
    scanning then bisecting (None if stable up to ``high``)."""
    def stable(nu):
        return spectral_radius(nu, geometry=geometry, ppc=ppc, shape=shape,
                               **scheme) <= 1 + growth

    grid = np.arange(low, high + 1e-9, 0.05)
    previous = None
    for nu in grid:
        if not stable(nu):
            if previous is None:
                return 0.0
            lo, hi = previous, nu
            while hi - lo > tolerance:
                mid = 0.5 * (lo + hi)
                if stable(mid):
                    lo = mid
                else:
                    hi = mid
            return lo
        previous = nu
    return None


def mode_frequency(theta, nu, geometry="1d", ppc=2, shape="linear",
                   **scheme):
    """(relative frequency error, energy factor per period) of the physical
    mode with wave number theta (= k h) at Courant number nu: the
    eigenvalue of the step closest to exp(i nu theta) in phase, among the
    eigenvalues with modulus above 0.5 (the acoustic branch).  Both
    numbers depend on theta and nu only (units: h = 1, c = 10)."""
    c, h = 10.0, 1.0
    dt = nu * h / c
    omega = c * theta / h
    cell = Cell(theta, geometry, ppc, shape=shape)
    eigenvalues = np.linalg.eigvals(step_matrix(cell, nu, c=c, h=h,
                                                **scheme))
    candidates = [z for z in eigenvalues if abs(z) > 0.5
                  and abs(cmath.phase(z)) > 1e-12]
    best = min(candidates, key=lambda z: abs(abs(cmath.phase(z))
                                             - omega * dt))
    omega_h = abs(cmath.phase(best)) / dt
    period_steps = 2 * math.pi / (omega_h * dt)
    return omega_h / omega - 1, abs(best) ** (2 * period_steps)


def _scheme_label(update, mass, order):
    names = {"lumped": "lumped", "full": "full", "consistent": "consistent",
             "fmpm": f"k={order}"}
    return f"{update} {names[mass]}"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--strain", default="usavg+",
                        choices=STRAIN_UPDATES)
    parser.add_argument("--update", default="fmpm", choices=PARTICLE_UPDATES)
    parser.add_argument("--ppc", type=int, default=None,
                        help="points per cell (default: 2 linear, p + 1 "
                        "B-splines)")
    parser.add_argument("--shape", default="linear", choices=SHAPES)
    arguments = parser.parse_args(argv)
    if arguments.shape != "linear":
        return bspline_table(arguments)
    if arguments.ppc is None:
        arguments.ppc = 2
    print(f"Critical Courant numbers (particle update "
          f"'{arguments.update}', strain update '{arguments.strain}', "
          f"{arguments.ppc} points per cell and direction)")
    print(f"{'mass matrix':14s} {'FE leapfrog':>12s} {'MPM 1D':>8s} "
          f"{'MPM strip':>10s}")
    for mass, order in [("lumped", 1), ("fmpm", 2), ("fmpm", 3),
                        ("fmpm", 5), ("fmpm", 10), ("full", 1),
                        ("consistent", 1)]:
        fe = fe_critical_courant("consistent" if mass == "full" else mass,
                                 order)
        values = []
        for geometry in ("1d", "strip"):
            nu = critical_courant(geometry, arguments.ppc,
                                  update=arguments.update, mass=mass,
                                  order=order, strain=arguments.strain)
            values.append("> 3" if nu is None else f"{nu:.3f}")
        label = mass if mass != "fmpm" else f"fmpm k={order}"
        print(f"{label:14s} {fe:12.3f} {values[0]:>8s} {values[1]:>10s}")
    return 0


def bspline_table(arguments):
    """Critical Courant numbers of the methods of doc/studies/bsplines.md
    on the periodic 1D line of B-spline cells (interior basis)."""
    ppc = arguments.ppc or shape_degree(arguments.shape) + 1
    print(f"Critical Courant numbers, {arguments.shape} on a periodic line "
          f"(strain update '{arguments.strain}', {ppc} points per cell)")
    methods = [("FLIP", dict(update="flip", mass="lumped"))]
    methods += [(f"FMPM({k})", dict(update="fmpm", mass="fmpm", order=k))
                for k in (2, 4, 8, 16)]
    methods += [("XPIC(5)", dict(update="xpic", mass="fmpm", order=5)),
                ("exact full mass", dict(update="fmpm", mass="full"))]
    for label, scheme in methods:
        nu = critical_courant("1d", ppc, shape=arguments.shape,
                              strain=arguments.strain, **scheme)
        print(f"{label:16s} {'> 3' if nu is None else f'{nu:.3f}':>8s}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
