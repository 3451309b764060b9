"""Compute the tables of ``src/sealeak/physics/_kinetic_slit.py`` (docs/theory.md §11.4).

* G_P(δ): the Poiseuille flow rate of an infinite plane channel, linearized BGK equation, diffuse walls.
  Cercignani's integral equation for the velocity w(x) across the channel (x in units of the height h,
  −1/2 < x < 1/2; Cercignani 1975, ch. V; Sharipov & Seleznev 1998, plane channel):

      w(x) = (1/√π) ∫ T₋₁(δ |x − s|) [δ w(s) + 1/2] ds,   G_P = 2 ∫ w dx,

  T_n(z) = ∫₀^∞ tⁿ exp(−t² − z/t) dt (Abramowitz's function; dT₀/dz = −T₋₁). Product integration on N
  equal cells (the cell integrals of the kernel exactly, (T₀(δ a) − T₀(δ b))/δ), N and 2N, Richardson
  extrapolation. Checks: G_P(1) = 1.5389 (Cercignani & Daneri 1963), G_P → δ/6 + 1.0162 (δ → ∞),
  G_P → −ln(δ)/√π + 3(1 − γ)/(2√π) (δ → 0).
* G_fm(ℓ) = ℓ W(ℓ)/√π: W the Clausing transmission probability of a two-dimensional slot of length ℓ
  heights with diffuse walls. The emission density ν(x) of a wall (per entering molecule) solves

      ν(x) = (1 − x/√(1 + x²))/2 + ∫₀^ℓ K(x − s) ν(s) ds,   K(ξ) = (1/2)(1 + ξ²)^(−3/2),

  (the view factors of infinitely long strips), and W = √(1 + ℓ²) − ℓ + 2 ∫ ν(s) (1 − (ℓ − s)/√(1 + (ℓ − s)²))/2 ds.
  Graded cells (finer at the ends), two refinements, Richardson extrapolation. Check: W(1) = 0.684.

Usage (from the repository root; a few minutes)::

    .venv/bin/python tools/kinetic_slit_tables.py
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad_vec

SQRT_PI = math.sqrt(math.pi)


def abramowitz_t0(z: np.ndarray) -> np.ndarray:
    """T₀(z) = ∫₀^∞ exp(−t² − z/t) dt for z >= 0 (vectorised adaptive quadrature, t = s/(1 − s))."""
    def f(s: float) -> np.ndarray:
        t = s / (1.0 - s)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            return np.nan_to_num(np.exp(-t * t - z / t) / (1.0 - s) ** 2)
    return np.asarray(quad_vec(f, 0.0, 1.0, epsabs=1e-15, epsrel=1e-13, limit=2000)[0])


def poiseuille_flow_rate(delta: float, n: int) -> float:
    """G_P(δ) on n equal cells."""
    dx = 1.0 / n
    t = abramowitz_t0(delta * (np.arange(n + 1) + 0.5) * dx)
    cell = np.empty(n)
    cell[0] = 2.0 * (0.5 * SQRT_PI - t[0]) / delta
    cell[1:] = (t[: n - 1] - t[1:n]) / delta
    a = cell[np.abs(np.subtract.outer(np.arange(n), np.arange(n)))] / SQRT_PI
    w = np.linalg.solve(np.eye(n) - delta * a, 0.5 * a.sum(axis=1))
    return float(2.0 * w.sum() * dx)


def _graded(ell: float, first: float, growth: float, largest: float) -> np.ndarray:
    half = [0.0]
    step = first
    while half[-1] + step < ell / 2:
        half.append(half[-1] + step)
        step = min(step * growth, largest)
    edges = np.array([*half, ell / 2])
    return np.concatenate([edges, ell - edges[::-1][1:]])


def transmission(ell: float, first: float, growth: float, largest: float) -> float:
    """W(ℓ) of the slot on graded cells."""
    e = _graded(ell, first, growth, largest)
    x = 0.5 * (e[1:] + e[:-1])

    def k_int(xi: np.ndarray) -> np.ndarray:
        return 0.5 * xi / np.sqrt(1.0 + xi * xi)

    d = x[:, None] - e[None, :]
    a = k_int(d[:, :-1]) - k_int(d[:, 1:])
    nu = np.linalg.solve(np.eye(x.size) - a, 0.5 * (1.0 - x / np.sqrt(1.0 + x * x)))

    def exit_int(s: np.ndarray) -> np.ndarray:
        return 0.5 * (s + np.sqrt(1.0 + (ell - s) ** 2))

    return float(math.sqrt(1.0 + ell * ell) - ell + 2.0 * nu @ (exit_int(e[1:]) - exit_int(e[:-1])))


def main() -> None:
    """Print both tables with their error estimates."""
    print("log10(delta)  G_P  (error estimate)")
    for k in np.round(np.arange(-40, 18) / 10.0, 1):
        d = 10.0**k
        n = max(400, math.ceil(40 * d / 100) * 100)
        a, b = poiseuille_flow_rate(d, n), poiseuille_flow_rate(d, 2 * n)
        print(f"{k:5.1f}  {b + (b - a) / 3:.7g}  ({abs(b - a) / 3:.1e})", flush=True)
    print("L/h  G_fm  (error estimate)")
    for ell in (1, 1.5, 2, 3, 5, 7, 10, 15, 20, 30, 50, 70, 100, 150, 200, 300, 500):
        a, b = transmission(ell, 0.01, 1.05, 0.25), transmission(ell, 0.005, 1.025, 0.125)
        g = (b + (b - a) / 3) * ell / SQRT_PI
        print(f"{ell:6g}  {g:.7g}  ({abs(b - a) / 3 * ell / SQRT_PI:.1e})", flush=True)


if __name__ == "__main__":
    main()
