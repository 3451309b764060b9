"""The exact route on height maps (sealeak.cases.simulation_map): the map itself is the surface."""

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from sealeak import simulate_map
from sealeak.cases import simulate, simulate_maps
from sealeak.cases.pipeline import cut_spectrum
from sealeak.cases.simulation_map import map_windows, solver_map
from sealeak.errors import InputError
from sealeak.numerics import synthesize
from sealeak.render.notes import worded
from sealeak.topography import Topography

GRID = 64
#: Low squeeze pressures, where the theory's critical junction spans many cells of a 64-point grid.
PRESSURES = np.array([20e3, 40e3])


@pytest.fixture(scope="module")
def low(case):
    return replace(case, squeeze_pressure=PRESSURES)


def _gaussian(case, seed, n=GRID):
    """A periodic Gaussian map of the case's spectrum, cut as the random route cuts it on an n-point grid."""
    spectrum, _, _ = cut_spectrum(case.spectrum, n, case.square_side, "grid", "critical-junction")
    return synthesize(spectrum, n, case.square_side, seed=np.random.default_rng([11, seed]))


def test_a_gaussian_periodic_map_gives_the_alpha_of_random_surfaces_of_its_spectrum(low):
    """Six synthetic maps through the map route against six random realisations: the mean α of each agrees
    within three combined standard errors (the theory of each map uses the C(q) the topography module
    estimates from that map, the random route the case's C(q))."""
    n = 6
    random = simulate(low, grid=GRID, realizations=n, seed=5, threshold=False)
    maps = [Topography(heights=_gaussian(low, s), size=(low.square_side, low.square_side), periodic=True, source=f"synthetic {s}")
            for s in range(n)]
    res = simulate_maps(maps, low, grid=GRID, threshold=False)
    assert res.percolates.all() and random.percolating_fraction.min() == 1.0
    assert all(m.periodic and not m.mirrored for m in res.maps)
    se = np.hypot(res.alpha_std, random.alpha_std) / np.sqrt(n)
    assert np.all(np.abs(res.alpha_mean - random.alpha) < 3.0 * se), (res.alpha_mean, random.alpha, se)
    assert np.all(res.alpha_effective_medium_mean > 0)  # both theories are reported, each map its own


def test_the_reported_skewness_and_kurtosis_are_those_of_the_levelled_heights(low):
    """A strongly skewed (plateau-like) map: its reported moments are scipy.stats' of the heights less their
    least-squares plane (kurtosis in Pearson's convention, 3 for Gaussian heights)."""
    g = _gaussian(low, 1, 32)
    h = -np.exp(-g / g.std())  # a plateau with deep valleys: negative skewness
    x, y = np.meshgrid(np.arange(32.0), np.arange(32.0), indexing="ij")
    a = np.stack([np.ones(h.size), x.ravel(), y.ravel()], axis=1)
    levelled = h.ravel() - a @ np.linalg.lstsq(a, h.ravel(), rcond=None)[0]
    res = simulate_map(h, low.square_side / 32, replace(low, squeeze_pressure=PRESSURES[:1]), grid=32, threshold=False)
    info = res.maps[0]
    assert stats.skew(levelled) < -1.0  # the test map is far from Gaussian
    assert info.skewness == pytest.approx(stats.skew(levelled), rel=1e-9)
    assert info.kurtosis == pytest.approx(stats.kurtosis(levelled, fisher=False), rel=1e-9)
    assert info.h_rms == pytest.approx(levelled.std(), rel=1e-9)


def test_a_tilted_non_periodic_map_is_levelled_mirrored_and_flagged(low):
    """A tilted plane plus roughness: the tilt is removed exactly (same result as without it), the map is
    mirrored into a periodic square (no step at its edges) and the result says so."""
    rough = _gaussian(low, 2, 32)
    ramp = 50.0 * rough.std() * np.linspace(-1.0, 1.0, 32)[:, None] + 20.0 * rough.std() * np.linspace(0.0, 1.0, 32)
    case = replace(low, squeeze_pressure=PRESSURES[:1])
    tilted = simulate_map(rough + ramp, low.square_side / 32, case, threshold=False)
    flat = simulate_map(rough, low.square_side / 32, case, threshold=False)
    info = tilted.maps[0]
    assert info.mirrored and not info.periodic and info.domain == pytest.approx(2.0 * info.side)
    assert any("levelled" in n and "mirrored" in n for n in worded(tilted.notes))
    assert tilted.leak_rate == pytest.approx(flat.leak_rate, rel=1e-6, abs=0)
    h = info.heights
    raw_step = np.abs((rough + ramp)[0] - (rough + ramp)[-1]).max()
    assert np.abs(h[0] - h[-1]).max() < 0.1 * raw_step and np.abs(h[:, 0] - h[:, -1]).max() < 0.1 * raw_step


def test_a_map_is_resampled_to_the_grid_asked_for_and_cut_into_windows(low):
    h = _gaussian(low, 3, 64)
    topo = Topography(heights=h, size=(low.square_side, low.square_side), source="m")
    info = solver_map(topo, 32)
    assert info.heights.shape == (32, 32) and any("resampled from 128x128 to the 32x32" in n for n in worded(info.notes))
    windows = map_windows(topo, 2)
    assert [w.nb_grid_pts for w in windows] == [(32, 32)] * 4 and windows[3].source == "m [window 2,2]"
    assert np.array_equal(windows[1].heights, h[:32, 32:])


@pytest.mark.parametrize(("heights", "pixel", "field", "value"), [
    (np.zeros((8, 40)), 1e-6, "heights", "(8, 40)"),
    (np.full((32, 32), np.nan), 1e-6, "heights", "non-finite"),
    (np.zeros((32, 32, 2)), 1e-6, "heights", "(32, 32, 2)"),
    (np.zeros(64), 1e-6, "heights", "(64,)"),
    (np.ones((32, 32)), float("nan"), "pixel_size", "nan"),
    (np.ones((32, 32)), -1e-6, "pixel_size", "-1e-06"),
    (np.ones((32, 32)), (1e-6, 1e-6, 1e-6), "pixel_size", "1e-06"),
])
def test_bad_maps_are_refused_naming_the_input(low, heights, pixel, field, value):
    h = np.array(heights)
    if h.ndim == 2 and np.isfinite(h).all():
        h = h + np.random.default_rng(0).normal(size=h.shape) * 1e-6
    with pytest.raises(InputError) as err:
        simulate_map(h, pixel, low)
    assert err.value.field == field and value in str(err.value)


def test_gas_cases_are_refused(low):
    """The map route simulates liquids (a stand-in for a gas case's conditions: only its name is read)."""
    gas_case = replace(low, gas=SimpleNamespace(gas=SimpleNamespace(name="air")))
    with pytest.raises(InputError, match="fluid.name = 'air'"):
        simulate_map(_gaussian(low, 4, 32), 1e-5, gas_case)
