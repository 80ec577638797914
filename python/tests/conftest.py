"""Shared helpers: closed forms used by several tests."""

import math


def damped(t: float, x0: float, v0: float, m: float, d: float, k: float) -> tuple[float, float]:
    """Closed form of m x'' + d x' + k x = 0 in all three regimes."""
    w0 = math.sqrt(k / m)
    zeta = d / (2 * math.sqrt(m * k))
    if abs(zeta - 1) < 1e-12:
        a, b = x0, v0 + w0 * x0
        e = math.exp(-w0 * t)
        return (a + b * t) * e, (b - w0 * (a + b * t)) * e
    if zeta < 1:
        wd = w0 * math.sqrt(1 - zeta * zeta)
        s = zeta * w0
        a, b = x0, (v0 + s * x0) / wd
        e = math.exp(-s * t)
        c, sn = math.cos(wd * t), math.sin(wd * t)
        return e * (a * c + b * sn), e * (-s * (a * c + b * sn) + wd * (-a * sn + b * c))
    root = math.sqrt(zeta * zeta - 1)
    r1, r2 = -w0 * (zeta - root), -w0 * (zeta + root)
    c1 = (v0 - r2 * x0) / (r1 - r2)
    c2 = x0 - c1
    return c1 * math.exp(r1 * t) + c2 * math.exp(r2 * t), r1 * c1 * math.exp(r1 * t) + r2 * c2 * math.exp(r2 * t)
