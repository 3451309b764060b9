"""Shared set-up of the numerics benchmarks: a self-affine surface and a load for a contact fraction."""

from __future__ import annotations

import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy.special import erfinv

from sealeak.numerics import synthesize
from sealeak.physics import PowerSpectrum

SIZE = 1e-3  # m
E_STAR = 1e6  # Pa


def surface(n: int, seed: int = 1) -> tuple[np.ndarray, PowerSpectrum]:
    """H = 0.8, q_r = 4·2π/L, cut-off at 1/8 of the Nyquist wavevector, h_rms = 1 µm."""
    q0 = 2 * np.pi / SIZE
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * q0, q_cutoff=np.pi * n / SIZE / 8,
                                   q_lowest=q0, h_rms=1e-6)
    return synthesize(sp, n, SIZE, seed=seed), sp


def pressure_for(sp: PowerSpectrum, fraction: float) -> float:
    """Persson's A/A0 = erf(P0/(2√G)), G = E*² slope²/8, times 0.8 (numerics give more area)."""
    g = E_STAR**2 * sp.slope_rms**2 / 8
    return 2 * math.sqrt(g) * float(erfinv(fraction)) * 0.8


CACHE = Path(__file__).resolve().parents[1] / "out" / "bench-cache"


def contact_gap(n: int, fraction: float, seed: int = 1) -> tuple[np.ndarray, np.ndarray, dict]:
    """Gap field (m) and contact mask of the FFT contact solution of ``surface(n, seed)`` at the load of
    ``pressure_for(fraction)``, tolerance 1e-8, cached in out/bench-cache (a 4096² contact solve takes
    minutes; the flow benchmark times the flow solve only). Returns (gap, contact, info)."""
    from sealeak.numerics import solve_contact

    path = CACHE / f"contact-{n}-{fraction:g}-{seed}.npz"
    if path.exists():
        with np.load(path) as z:
            return z["gap"], z["contact"], json.loads(str(z["info"]))
    h, sp = surface(n, seed)
    t = time.perf_counter()
    c = solve_contact(h, SIZE, E_STAR, pressure_for(sp, fraction))
    info = dict(seconds=time.perf_counter() - t, iterations=c.iterations, area=c.contact_area, residual=c.residual)
    CACHE.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".part.npz")
    np.savez(tmp, gap=c.gap, contact=c.contact, info=json.dumps(info))
    os.replace(tmp, path)
    return c.gap, c.contact, info


def take_option(name: str, default: str) -> str:
    """The value after ``name`` on the command line (removed from ``sys.argv``), or ``default``."""
    if name in sys.argv:
        i = sys.argv.index(name)
        value = sys.argv[i + 1]
        del sys.argv[i:i + 2]
        return value
    return default
