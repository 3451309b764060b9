"""Published numbers that sealeak reproduces, each recomputed here (the table of docs/validation.md).

Usage: python benchmarks/validation.py [--quick] [--only NAME ...] [--write]

One function per row (NAME: percolation, kappa, kappa_persson, gamma, hertz, lindley). Each returns the
published value with its source, sealeak's value (with a standard error where realisations scatter)
and the tolerance within which the two should agree; ``--quick`` runs small grids and few
realisations (seconds a row; tests/integration/test_validation.py runs it), the default the grids the
page quotes (a minute or two a row on two cores). ``--write`` (every row, no ``--only``) replaces the generated table of
docs/validation.md (between its ``validation:begin``/``validation:end`` markers) with these rows, the
machine and the date; without it the table is printed.

All rows use sealeak's own code paths: ``numerics.percolation_threshold`` and ``solve_contact`` on
``numerics.synthesize`` surfaces, ``cases.convergence.extrapolate`` for the continuum limit,
``physics.PerssonContact`` for the theory, ``numerics.solve_band_contact`` and ``physics.oring_contact``.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from sealeak.cases.convergence import PUBLISHED_THRESHOLDS, extrapolate, standard_error  # noqa: E402
from sealeak.numerics import (  # noqa: E402
    contact_edges,
    hertz_line_contact,
    percolation_threshold,
    solve_band_contact,
    solve_contact,
    synthesize,
)
from sealeak.physics import PerssonContact, PowerSpectrum, oring_contact  # noqa: E402
from sealeak.physics._kinetic_slit import poiseuille_flow_rate  # noqa: E402

PAGE = ROOT / "docs" / "validation.md"
BEGIN, END = "<!-- validation:begin -->", "<!-- validation:end -->"
SIZE = 1e-3  # m, side of the periodic square
E_STAR = 1e6  # Pa
Q0 = 2 * math.pi / SIZE


@dataclass(frozen=True)
class Row:
    """One published number against sealeak's; ``tolerance`` is the allowed |sealeak - published|."""

    quantity: str
    published: float
    source: str
    value: float
    stderr: float  # NaN where sealeak's number has no sampling error
    tolerance: float
    conditions: str

    @property
    def ratio(self) -> float:
        return self.value / self.published

    @property
    def agrees(self) -> bool:
        return abs(self.value - self.published) <= self.tolerance


def _spectrum(q_rolloff: float, q_cutoff: float) -> PowerSpectrum:
    return PowerSpectrum.self_affine(hurst=0.8, q_rolloff=q_rolloff * Q0, q_cutoff=q_cutoff * Q0,
                                     q_lowest=Q0, h_rms=1e-6)


def _continuum(grids: tuple[int, ...], samples: Callable[[int], list[float]]) -> tuple[float, float, str]:
    """Mean ± standard error per grid, extrapolated to the continuum (a → 0, p = 1) over the grids."""
    stats = [standard_error(samples(n)) for n in grids]
    per_grid = ", ".join(f"{m:.3f} ± {se:.3f} ({n}²)" for (m, se, _), n in zip(stats, grids, strict=True))
    fit = extrapolate([SIZE / n for n in grids], [m for m, _, _ in stats], [se for _, se, _ in stats], exponent=1.0)
    return fit.value, fit.stderr, per_grid


def percolation(quick: bool) -> Row:
    """Relative contact area at which the non-contact area stops percolating (numerically exact route)."""
    grids, reps = ((64, 128), 4) if quick else ((64, 128, 256), 12)

    def samples(n: int) -> list[float]:
        sp = _spectrum(4, n / 8)  # the spectrum's cut-off follows the grid: 8 cells per shortest wavelength
        scale = E_STAR * sp.slope_rms
        return [percolation_threshold(synthesize(sp, n, SIZE, seed=r), SIZE, E_STAR, p_lo=0.02 * scale,
                                      p_hi=0.6 * scale, rel_tol=1e-2).contact_area for r in range(reps)]

    value, se, per_grid = _continuum(grids, samples)
    source, published = PUBLISHED_THRESHOLDS[1]
    return Row("percolation threshold A/A0 (self-affine, H = 0.8)", published, source, value, se, max(0.05, 3 * se),
               f"{reps} realisations per grid: {per_grid}; extrapolated linearly in the grid spacing")


def kappa(quick: bool) -> Row:
    """κ of A/A0 = κ P0/(E* h'_rms) at small load, extrapolated in the grid for a fixed spectrum."""
    grids, reps = ((64, 128), 4) if quick else ((128, 256, 512), 8)
    sp = _spectrum(2, 16)
    g = sp.slope_rms
    pressure = 0.015 * E_STAR * g

    def samples(n: int) -> list[float]:
        return [solve_contact(synthesize(sp, n, SIZE, seed=r), SIZE, E_STAR, pressure).contact_area * E_STAR * g / pressure
                for r in range(reps)]

    value, se, per_grid = _continuum(grids, samples)
    return Row("κ in A/A0 = κ P0/(E* h'_rms), small load", 2.0,
               "numerical contact mechanics: ≈ 2 (Hyun et al., PRE 70 (2004) 026117; Prodanov, Dapp & Müser, "
               "Tribol. Lett. 53 (2014) 433); Persson's theory √(8/π) ≈ 1.60",
               value, se, max(0.3, 3 * se),
               f"P0 = 0.015 E* h'_rms, H = 0.8, q_r = 2q0, q1 = 16q0; {reps} realisations per grid: {per_grid}; "
               "extrapolated linearly in the grid spacing")


def kappa_persson(quick: bool) -> Row:
    """κ of Persson's theory (eq. 2.4 at small load): A/A0 → P0/√(πG), G(ζ1) = E*² h'_rms²/8."""
    sp = _spectrum(2, 16)
    contact = PerssonContact(sp, E_STAR, Q0, 1.0)
    pressure = 1e-4 * E_STAR * sp.slope_rms
    area = float(np.asarray(contact.area(contact.zeta_max, pressure)))
    return Row("κ of Persson's theory (same definition, P0 → 0)", math.sqrt(8 / math.pi),
               "Persson, J. Chem. Phys. 115 (2001) 3840: κ = √(8/π); quoted e.g. by Paggi & Ciavarella, Wear (2010)",
               area * E_STAR * sp.slope_rms / pressure, float("nan"), 1e-3,
               "physics.PerssonContact.area at ζ1, P0 = 10⁻⁴ E* h'_rms")


def gamma(quick: bool) -> Row:
    """The γ with which Persson's mean gap ū(1) (eq. 2.8) fits sealeak's numerically exact mean gaps."""
    n, reps = (128, 2) if quick else (512, 4)
    sp = _spectrum(2, 16)
    loads = E_STAR * sp.slope_rms * np.array([0.02, 0.05, 0.1, 0.2])
    numeric = np.array([[solve_contact(synthesize(sp, n, SIZE, seed=r), SIZE, E_STAR, float(p)).mean_gap for p in loads]
                        for r in range(reps)]).mean(axis=0)

    def misfit(gam: float) -> float:
        theory = PerssonContact(sp, E_STAR, Q0, gam).mean_gap(1.0, loads)
        return float(np.sum(np.log(np.asarray(theory) / numeric) ** 2))

    best = minimize_scalar(misfit, bounds=(0.05, 1.0), method="bounded", options={"xatol": 1e-3})
    ratio_042 = np.asarray(PerssonContact(sp, E_STAR, Q0, 0.42).mean_gap(1.0, loads)) / numeric
    ratio_1 = np.asarray(PerssonContact(sp, E_STAR, Q0, 1.0).mean_gap(1.0, loads)) / numeric
    return Row("γ of Persson's mean gap ū (eq. 2.8) fitted to exact mean gaps", 0.42,
               "Yang & Persson, JPCM 20 (2008) 215214; Almqvist et al., JMPS 59 (2011) 2355", float(best.x),
               float("nan"), 0.2,
               f"{n}², {reps} realisations, P0/(E* h'_rms) = 0.02–0.2; ū_theory/ū_exact "
               f"{ratio_042.min():.2f}–{ratio_042.max():.2f} with γ = 0.42, {ratio_1.min():.2f}–{ratio_1.max():.2f} with γ = 1")


def hertz(quick: bool) -> Row:
    """Peak pressure of a smooth cylinder on a flat by the band contact solver, against Hertz (eq. 10.13)."""
    n = 128 if quick else 512
    radius, half_width, e_star = 1e-3, 0.25e-3, 3e6
    f = math.pi * e_star * half_width**2 / (4 * radius)
    width = 5 * half_width
    res = solve_band_contact(np.zeros((n, 1)), width, width, e_star, radius, f)
    b, p_max = hertz_line_contact(f, radius, e_star)
    lo, hi = contact_edges(res.x, res.line_pressure)
    return Row("peak pressure of a cylinder on a flat (the O-ring's small-squeeze limit)", p_max,
               "Hertz (Johnson 1985, ch. 4): p_max = 2f/(πb), b = √(4fR/(πE*))",
               res.max_pressure, float("nan"), 0.01 * p_max,
               f"{n} cells across 2.5 contact widths; contact width {(hi - lo) / (2 * b):.4f} × Hertz's 2b")


def lindley(quick: bool) -> Row:
    """Force per length of an O-ring at 20 % squeeze, against Lindley's published relation (eq. 10.6)."""
    d, e, eps = 3.53e-3, 5e6, 0.2
    published = e * d * (1.25 * eps**1.5 + 50 * eps**6)  # Lindley (1967), written out
    c = oring_contact(d, e, 0.5, eps)
    return Row("O-ring force per length at 20 % squeeze (N/m)", published,
               "Lindley, J. Inst. Rubber Ind. 1 (1967) 202: f = E d (1.25 ε^1.5 + 50 ε^6); "
               "handbook load–compression charts: not compared (no handbook table in the repository)",
               float(np.asarray(c.force_per_length).ravel()[0]), float("nan"), 1e-9 * published,
               "d = 3.53 mm, E = 5 MPa, ν = 0.5")


def kinetic_slit(quick: bool) -> Row:
    """The Poiseuille flow rate G_P(δ = 1) of a slit, linearized BGK with diffuse walls (eq. 11.5), from sealeak's table."""
    published = 1.5389  # Cercignani & Daneri (1963); Sharipov & Seleznev (1998), plane channel, BGK
    return Row("Poiseuille flow rate G_P(δ = 1) of a slit (linearized BGK, diffuse walls)", published,
               "Cercignani & Daneri, J. Appl. Phys. 34 (1963) 3509; Sharipov & Seleznev, J. Phys. Chem. Ref. Data 27 "
               "(1998) 657", float(poiseuille_flow_rate(1.0)), float("nan"), 1e-3 * published,
               "sealeak's table, solved from Cercignani's integral equation by tools/kinetic_slit_tables.py")


def kinetic_free_molecular(quick: bool) -> Row:
    """G_P(δ) + ln(δ)/√π at δ = 10⁻⁴, the smallest tabulated δ, against Cercignani's free-molecular constant."""
    published = 1.5 * (1.0 - float(np.euler_gamma)) / math.sqrt(math.pi)  # 3(1 − γ)/(2√π), written out
    delta = 1e-4
    return Row("free-molecular limit of the slit: G_P(δ) + ln(δ)/√π as δ → 0", published,
               "Cercignani, Theory and Application of the Boltzmann Equation (1975): G_P → −ln(δ)/√π + 3(1 − γ)/(2√π)",
               float(poiseuille_flow_rate(delta)) + math.log(delta) / math.sqrt(math.pi), float("nan"), 0.01,
               "δ = 10⁻⁴, the smallest δ of sealeak's table (the next term, of order δ ln²δ, is below 10⁻²)")


ROWS: dict[str, Callable[[bool], Row]] = dict(percolation=percolation, kappa=kappa, kappa_persson=kappa_persson,
                                               gamma=gamma, hertz=hertz, lindley=lindley, kinetic_slit=kinetic_slit,
                                               kinetic_free_molecular=kinetic_free_molecular)


def _number(x: float) -> str:
    return f"{x:.4g}" if math.isfinite(x) else "–"


def table(rows: list[Row], quick: bool) -> str:
    machine = f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.system()}, Python {platform.python_version()}"
    date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [f"Generated by `python benchmarks/validation.py{' --quick' if quick else ''} --write` on {machine}, {date}.", "",
             "| quantity | published (source) | sealeak | ratio | agrees | conditions |", "|---|---|---|---|---|---|"]
    for r in rows:
        value = _number(r.value) + (f" ± {_number(r.stderr)}" if math.isfinite(r.stderr) else "")
        lines.append(f"| {r.quantity} | {_number(r.published)} ({r.source}) | {value} | {r.ratio:.3f} | "
                     f"{'yes' if r.agrees else 'NO'} (±{_number(r.tolerance)}) | {r.conditions} |")
    return "\n".join(lines)


def write(text: str, page: Path = PAGE) -> None:
    doc = page.read_text(encoding="utf-8")
    block = re.compile(re.escape(BEGIN) + ".*?" + re.escape(END), re.S)
    if not block.search(doc):
        raise SystemExit(f"{page}: no {BEGIN} … {END} block")
    page.write_text(block.sub(lambda _: f"{BEGIN}\n{text}\n{END}", doc), encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small grids and few realisations (seconds a row)")
    parser.add_argument("--only", nargs="+", choices=sorted(ROWS), help="these rows only")
    parser.add_argument("--write", action="store_true", help=f"replace the table in {PAGE.relative_to(ROOT)}")
    args = parser.parse_args(argv)
    if args.write and args.only:
        parser.error("--write rewrites the whole table: run every row (no --only)")
    rows = [ROWS[name](args.quick) for name in (args.only or ROWS)]
    text = table(rows, args.quick)
    if args.write:
        write(text)
    print(text)
    return 0 if all(r.agrees for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
