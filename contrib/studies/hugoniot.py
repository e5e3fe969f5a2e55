#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Rankine-Hugoniot jump of fmpm's 'mie gruneisen' model in uniaxial strain.

A shock driven by a piston at u_p into material at rest: mass,
momentum and energy jumps (seed 004 Sec. 4.3 validation)
    eta = 1 - J = u_p / U_s,   -sigma_xx = rho0 U_s u_p,   U = u_p^2 / 2,
with the model's sigma_xx(J, U) = -p(eta, U) + s_xx(J): Eq. 51 for p and
the Eq. 18 shear term s_xx = (2/3) G J^(-5/3) (J^2 - 1) (no plasticity).
"""
import math


def pressure(eta, U, K, gamma0, S1, rho0):
    """Eq. 51 (energy term in compression only, as the model)."""
    if eta <= 0:
        return K * eta
    return (K * eta * (1 - 0.5 * gamma0 * eta) / (1 - S1 * eta) ** 2
            + rho0 * gamma0 * U)


def sigma_xx(eta, U, K, G, gamma0, S1, rho0):
    J = 1 - eta
    shear = 2.0 / 3.0 * G * J ** (-5.0 / 3.0) * (J * J - 1)
    return -pressure(eta, U, K, gamma0, S1, rho0) + shear


def jump(up, K, G, gamma0, S1, rho0):
    """(U_s, sigma_xx, J, U) behind a steady shock of particle speed up."""
    U = 0.5 * up * up

    def residual(eta):
        return -sigma_xx(eta, U, K, G, gamma0, S1, rho0) - rho0 * up * up / eta

    lo, hi = 1e-12, (1.0 / S1) * (1 - 1e-9)
    # residual < 0 for small eta (rho0 up^2/eta dominates), > 0 near 1/S1
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if residual(mid) > 0:
            hi = mid
        else:
            lo = mid
    eta = 0.5 * (lo + hi)
    Us = up / eta
    return Us, -rho0 * Us * up, 1 - eta, U


if __name__ == "__main__":
    nickel = dict(K=188e9, G=76e9, gamma0=2.0, S1=1.44, rho0=8870.0)
    print("C0 = %.1f m/s" % math.sqrt(nickel["K"] / nickel["rho0"]))
    for up in (100, 250, 500, 1000, 1840):
        Us, s, J, U = jump(up, **nickel)
        print("u_p %6.0f  U_s %7.1f  sigma_xx %10.4g  J %.4f  U %.4g" % (up, Us, s, J, U))
