"""P(u) and the effective medium's discretisation kept for reuse (physics/gaps.py, "Reuse"): what comes from the
cache is what a fresh computation gives, a different contact never takes another's rows, and the cache stays
within its bytes."""

import importlib
from dataclasses import replace

import numpy as np
import pytest

from sealeak import PowerSpectrum
from sealeak.cases import example_path, load_cases
from sealeak.physics import gaps
from sealeak.physics.contact import PerssonContact, contact_modulus
from sealeak.physics.effective_medium import effective_medium

E_STAR = contact_modulus(2.3e6, 0.5)
Q0 = 2 * np.pi / 5e-3
em_module = importlib.import_module("sealeak.physics.effective_medium")  # (the package exports the function by that name)
FIELDS = [f for f in gaps._FIELDS if f != "squeeze_pressure"]


def make_contact(q0=Q0, e_star=E_STAR):
    s = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=9.1e3, q_cutoff=2 * np.pi / 20e-6, q_lowest=Q0, h_rms=44e-6)
    return PerssonContact(s, e_star, q0, gamma=1.0)


@pytest.fixture(autouse=True)
def cold():
    gaps.clear_caches()
    yield
    gaps.clear_caches()


def fresh(contact, p):
    """Each row computed on its own, nothing kept."""
    return [gaps._compute(contact, np.array([x]), 32, 64, 20, 8, 1e-14) for x in p]


def test_rows_from_the_cache_are_those_computed_alone():
    contact = make_contact()
    gaps.gap_distribution(contact, [3e4, 2e5])  # kept
    p = np.array([2e5, 7e4, 3e4, 7e4])  # two kept, one new (asked twice), out of order
    got = gaps.gap_distribution(contact, p)
    assert np.array_equal(got.squeeze_pressure, p)
    for i, alone in enumerate(fresh(contact, p)):
        for name in FIELDS:
            assert np.array_equal(getattr(got, name)[i], getattr(alone, name)[0]), name
    assert len(gaps._ROWS) == 3


def test_another_contact_does_not_take_the_rows():
    p = [1e5]
    base = gaps.gap_distribution(make_contact(), p)
    for other in (make_contact(q0=1.01 * Q0), make_contact(e_star=1.01 * E_STAR)):
        got = gaps.gap_distribution(other, p)
        assert not np.allclose(got.centres, base.centres, rtol=1e-6)
        assert np.array_equal(got.centres, fresh(other, p)[0].centres)


def test_the_cache_keeps_within_its_bytes(monkeypatch):
    contact = make_contact()
    one = gaps.gap_distribution(contact, [1e5])
    row = sum(np.asarray(getattr(one, f)[0]).nbytes for f in gaps._FIELDS)
    monkeypatch.setattr(gaps, "GAP_CACHE_BYTES", int(2.5 * (row + 200)))
    gaps.gap_distribution(contact, np.geomspace(2e4, 3e5, 5))
    assert len(gaps._ROWS) == 2 and gaps._ROWS.nbytes <= gaps.GAP_CACHE_BYTES
    # the most recent ones are kept
    assert gaps._ROWS.get((gaps.contact_key(contact, 32, 64, 20, 8, 1e-14), 3e5)) is not None


def test_a_second_fluid_computes_no_gap_distribution_and_gets_the_same_bits(monkeypatch):
    contact = make_contact()
    p = np.geomspace(2e4, 3e5, 4)

    def run(eta):
        return effective_medium(contact, squeeze_pressure=p, pressure_difference=1e5, viscosity=eta, aspect_ratio=1.0)

    cold_oil = run(0.03).effective_conductivity
    gaps.clear_caches()
    water = run(1e-3)
    calls = []
    real = gaps._compute
    monkeypatch.setattr(gaps, "_compute", lambda *a: calls.append(a) or real(*a))
    monkeypatch.setattr(em_module, "discretise", lambda *a, **k: calls.append(a))
    oil = run(0.03)
    assert calls == []
    assert np.array_equal(oil.effective_conductivity, cold_oil)
    # σ_eff ∝ 1/η (docs/theory.md §5.3): the two fluids' σ differ by the ratio of the viscosities alone
    assert np.allclose(oil.effective_conductivity * 0.03, water.effective_conductivity * 1e-3, rtol=1e-13, atol=0)
    assert (water.effective_conductivity > 0).all()


def test_critical_junctions_from_the_cache_are_those_computed_alone(monkeypatch):
    """A critical junction is a function of the contact, the threshold and its own pressure alone: a list, its
    pressures one at a time and the list again (all kept) give the same bits; a second viscosity, α or ΔP computes no
    junction again, and another threshold does not take the kept rows."""
    cj_module = importlib.import_module("sealeak.physics.critical_junction")
    contact = make_contact()
    p = np.geomspace(2e4, 3e5, 7)

    def run(pressures, eta=1e-3, alpha=1.0, threshold=0.6):
        return cj_module.critical_junction(contact, squeeze_pressure=pressures, pressure_difference=1e5, viscosity=eta,
                                           aspect_ratio=1.0, alpha=alpha, percolation_threshold=threshold)

    together = run(p)
    for i, x in enumerate(p):
        gaps.clear_caches()
        alone = run([x])
        for name in ("critical_gap", "critical_magnification", "contact_area_at_cutoff", "leak_rate"):
            assert np.array_equal(getattr(alone, name)[0], getattr(together, name)[i], equal_nan=True), name
    gaps.clear_caches()
    run(p)
    computed = []
    new = cj_module._new_junctions
    monkeypatch.setattr(cj_module, "_new_junctions", lambda c, t, x: computed.append(x.size) or new(c, t, x))
    again = run(p[::-1], eta=0.03, alpha=0.4)
    assert computed == []
    assert np.array_equal(again.critical_gap[::-1], together.critical_gap)
    assert np.allclose(again.leak_rate[::-1], together.leak_rate * 0.4 / 30, rtol=1e-14)
    other = run(p, threshold=0.5)
    assert computed == [p.size] and not np.allclose(other.critical_gap, together.critical_gap, equal_nan=True)


def test_the_band_keeps_sigma_eff_by_its_list_of_pressures(monkeypatch):
    """σ_eff is kept by contact, viscosity and the exact list of pressures (P(u) is discretised over the list): the
    same list again is answered without the effective medium, with the bits of a fresh computation; another viscosity
    or another list is computed."""
    band = importlib.import_module("sealeak.cases.band_tables")
    case = load_cases(example_path("o-ring"))[0]
    contact = band.persson_contact(case, float(case.band.q0[4]))
    p = np.geomspace(1e4, 1e6, 5)
    first = band.effective_medium_exact(case, contact)(p)
    gaps.clear_caches()
    fresh_values = band.effective_medium_exact(case, contact)(p)
    assert np.array_equal(first, fresh_values)
    calls = []
    em = band.effective_medium
    monkeypatch.setattr(band, "effective_medium", lambda *a, **k: calls.append(1) or em(*a, **k))
    assert np.array_equal(band.effective_medium_exact(case, contact)(p.copy()), first) and calls == []
    band.effective_medium_exact(case, contact)(p[:3])
    thicker = band.effective_medium_exact(replace(case, fluid=replace(case.fluid, viscosity=0.03)), contact)(p)
    assert len(calls) == 2
    assert np.allclose(thicker, first * case.fluid.viscosity / 0.03, rtol=1e-12)
