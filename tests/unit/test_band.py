"""Seals with a non-uniform contact pressure: the series-strip leak rate (docs/theory.md §10.1)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy import integrate

from sealeak.cases import example_path, load_case, predict, predict_effective_medium, run_case
from sealeak.cases.band import run_band
from sealeak.cases.model import BandSeal
from sealeak.cases.notes import Note
from sealeak.errors import InputError
from sealeak.physics.contact import PerssonContact
from sealeak.physics.critical_junction import critical_junction
from sealeak.physics.profile import (
    GAUSS_WEIGHTS,
    KRONROD_NODES,
    KRONROD_WEIGHTS,
    PressureProfile,
    resistance_band,
    series_resistance,
)


@pytest.fixture(scope="module")
def base():
    """The reference experiment as a uniform seal of width Lx (q0 = 2π/Lx)."""
    return load_case(example_path("reference-experiment"))


def _band(case, profiles, q0=None, faces=1):
    n = len(profiles)
    return replace(case, band=BandSeal(kind="profile", length=case.seal.length, load_name="profile_scale",
                                       loads=np.ones(n), profiles=tuple(profiles),
                                       q0=np.full(n, case.q0 if q0 is None else q0), faces=faces))


# ---------------------------------------------------------------------- the profile itself
def test_semi_elliptic_profile_carries_its_force():
    p = PressureProfile.semi_elliptic(1.2e-3, 1.7e6)
    f, _ = integrate.quad(lambda x: float(p.at(x)), 0.0, p.width, limit=200)
    assert f == pytest.approx(p.force_per_length, rel=1e-7)
    assert p.mean_pressure == pytest.approx(f / 1.2e-3, rel=1e-7)
    assert p.at(0.6e-3) == pytest.approx(1.7e6)
    assert p.at(0.0) == 0.0 and p.at(1.2e-3) == 0.0


def test_table_profile_force_mean_and_scale():
    p = PressureProfile.table([1.0, 2.0, 2.0, 4.0], [1e5, 1e5, 3e5, 3e5])  # shifted to start at 0
    assert p.width == 3.0
    assert p.force_per_length == pytest.approx(1e5 * 1 + 3e5 * 2)
    assert p.scaled(2.0).max_pressure == 6e5
    assert p.at(1.5) == 3e5  # after the step


@pytest.mark.parametrize("x, p, field", [
    ([0, 1], [1, 2, 3], "x"),
    ([0, 2, 1], [1, 1, 1], "x[2]"),
    ([0, 1], [1, -1], "pressure[1]"),
    ([0, 0], [1, 1], "x"),
    ([0, 1], [0, 0], "pressure"),
    ([0, np.nan], [1, 1], "x"),
])
def test_table_profile_refuses_nonsense(x, p, field):
    with pytest.raises(InputError) as err:
        PressureProfile.table(x, p)
    assert err.value.field == field


# ---------------------------------------------------------------------- limits of the series integral
def test_constant_profile_reproduces_the_uniform_seal(base):
    """A constant profile over the seal's width is today's uniform seal, both theories: the critical junction to 1e-10,
    the effective medium to 1e-6 (a band's σ_eff takes the lighter ζ-rule of σ tables, within 6e-7 of the default)."""
    case = replace(base, model="both")
    for p0 in (2e4, 1e5, 4e5):
        r = run_band(_band(case, [PressureProfile.table([0, case.seal.width], [p0, p0])]))
        cj = predict(case, squeeze_pressure=[p0]).leak_rate[0]
        em = predict_effective_medium(case, squeeze_pressure=[p0]).leak_rate[0]
        assert r.critical_junction.leak_rate[0] == pytest.approx(cj, rel=1e-10, abs=0)
        assert r.effective_medium.leak_rate[0] == pytest.approx(em, rel=1e-6, abs=0)  # (1.3e-7 here)
        assert r.critical_junction.uniform_mean_pressure[0] == pytest.approx(cj, rel=1e-10, abs=0)


def test_step_profile_is_the_series_sum(base):
    """Two pressures side by side: 1/K = (w1/σ1 + w2/σ2)/Ly: the critical junction to 1e-8, the effective medium to
    1e-6 (its band σ_eff takes the lighter ζ-rule of σ tables)."""
    case = replace(base, model="both")
    w, ly, dp = case.seal.width, case.seal.length, case.pressure_difference
    w1 = 0.3 * w
    p1, p2 = 3e4, 2e5
    r = run_band(_band(case, [PressureProfile.table([0, w1, w1, w], [p1, p1, p2, p2])]))
    for theory, fn in (("critical_junction", predict), ("effective_medium", predict_effective_medium)):
        s1 = fn(case, squeeze_pressure=[p1], pressure_difference=1.0).leak_rate[0] * w / ly  # σ = K Lx/Ly
        s2 = fn(case, squeeze_pressure=[p2], pressure_difference=1.0).leak_rate[0] * w / ly
        expect = ly * dp / (w1 / s1 + (w - w1) / s2)
        assert getattr(r, theory).leak_rate[0] == pytest.approx(expect, rel=1e-8 if theory == "critical_junction" else 1e-6,
                                                                abs=0)


def test_a_sealed_strip_seals_the_band(base):
    """A high-pressure strip that does not percolate gives no leak channel, whatever the rest."""
    w = base.seal.width
    high = 5e6  # far above the pressure where the reference surface stops percolating
    assert not predict(base, squeeze_pressure=[high]).percolates[0]
    r = run_band(_band(base, [PressureProfile.table([0, 0.9 * w, 0.9 * w, w], [2e4, 2e4, high, high])]))
    assert not r.critical_junction.percolates[0]
    assert np.isnan(r.critical_junction.leak_rate[0])
    sealed = [n for n in r.critical_junction.messages if isinstance(n, Note) and n.code == "band_sealed"]
    assert [n.values["loads"] for n in sealed] == [tuple(r.band.loads.tolist())]


def test_unpressed_strip_adds_no_resistance(base):
    """Open gaps (p = 0) beside a pressed band change nothing; faces = 2 doubles Q."""
    w, p0 = base.seal.width, 1e5
    alone = run_band(_band(base, [PressureProfile.table([0, w], [p0, p0])]))
    widened = run_band(_band(base, [PressureProfile.table([0, w, w, 3 * w], [p0, p0, 0.0, 0.0])]))
    assert widened.critical_junction.leak_rate[0] == pytest.approx(alone.critical_junction.leak_rate[0], rel=1e-12, abs=0)
    two = run_band(_band(base, [PressureProfile.table([0, w], [p0, p0])], faces=2))
    assert two.critical_junction.leak_rate[0] == pytest.approx(2 * alone.critical_junction.leak_rate[0], rel=1e-12, abs=0)


def test_hertz_integral_converges_to_an_independent_quadrature(base):
    """R of a Hertz band against scipy's adaptive quad of 1/σ(p(x)) in x (σ from the theory itself)."""
    w, pmax = base.seal.width, 1.5e5
    contact = PerssonContact(base.spectrum, base.e_star, base.q0, base.gamma)

    def inv_sigma(x: float) -> float:
        p = float(PressureProfile.semi_elliptic(w, pmax).at(x))
        if p <= 0:
            return 0.0
        res = critical_junction(contact, squeeze_pressure=[p], pressure_difference=1.0, viscosity=base.fluid.viscosity,
                                aspect_ratio=1.0, alpha=base.alpha, percolation_threshold=base.percolation_threshold)
        return 1.0 / res.leak_rate[0]

    ref, err = integrate.quad(inv_sigma, 0.0, w, epsabs=0.0, epsrel=1e-11, limit=400)
    r = run_band(_band(base, [PressureProfile.semi_elliptic(w, pmax)]))
    assert r.critical_junction.change[0] < 1e-8
    assert r.critical_junction.resistance[0] == pytest.approx(ref, rel=1e-8)
    # convexity of 1/σ(p) (Jensen): the mean pressure leaks more than the real band
    assert r.critical_junction.leak_rate[0] < r.critical_junction.uniform_mean_pressure[0]


def test_resistance_band_of_a_step():
    """Density 1 on [0, 1], 4 on [1, 2]: 90 % of R = 4.5 lies in 1.5 of width, the peak on the high piece."""
    prof = PressureProfile.table([0, 1, 1, 2], [1.0, 1.0, 2.0, 2.0])
    g = series_resistance(prof, lambda p: 1.0 / p**2)
    assert g.resistance == pytest.approx(5.0)
    width, peak = resistance_band(g)
    assert width == pytest.approx(1.5)
    assert 1.0 <= peak <= 2.0


def test_q0_is_per_load_by_default_and_changes_the_result(base):
    """The band's own width sets q0 = 2π/w; a case-wide q0 is another, stated, choice."""
    w = base.seal.width
    prof = [PressureProfile.table([0, 2 * w], [1e5, 1e5])]
    own = run_band(_band(base, prof, q0=2 * np.pi / (2 * w)))
    wide = replace(base, seal=replace(base.seal, width=2 * w), q0=2 * np.pi / (2 * w))
    assert own.critical_junction.leak_rate[0] == pytest.approx(predict(wide, squeeze_pressure=[1e5]).leak_rate[0], rel=1e-10, abs=0)


def test_kronrod_rule_is_exact_for_polynomials():
    """K15 integrates degree 22 exactly, its embedded G7 degree 13 (the error estimate is their difference)."""
    for deg in range(0, 23):
        exact = 0.0 if deg % 2 else 2.0 / (deg + 1)
        assert KRONROD_WEIGHTS @ KRONROD_NODES**deg == pytest.approx(exact, abs=1e-14)
        if deg <= 13:
            assert GAUSS_WEIGHTS @ KRONROD_NODES**deg == pytest.approx(exact, abs=1e-14)
    assert np.allclose(np.sort(KRONROD_NODES[1::2]), np.polynomial.legendre.leggauss(7)[0], atol=1e-15)


@pytest.mark.parametrize("decades", [1, 10, 26])
def test_steep_conductance_near_the_peak_converges_to_the_closed_form(decades):
    """1/σ = exp(a p) on a ramp 0 → p_max: R = w (e^{a p_max} - 1)/(a p_max), 1/σ spanning up to 26 decades."""
    w, pmax = 1e-3, 2e6
    a = decades * np.log(10) / pmax
    g = series_resistance(PressureProfile.table([0, w], [0, pmax]), lambda p: np.exp(-a * p))
    exact = w * np.expm1(a * pmax) / (a * pmax)
    assert g.converged and g.change < 1e-8
    assert g.resistance == pytest.approx(exact, rel=1e-8)


def test_gas_through_a_band_uses_each_theorys_narrowest_constriction():
    """Rarefaction gap of a band seal: u_c at the peak (critical junction), (12 μ σ_min)^(1/3) (effective medium)."""
    case = load_case(example_path("helium-test"))
    band = replace(case.band, loads=case.band.loads[:1], profiles=case.band.profiles[:1], q0=case.band.q0[:1])
    res = run_case(replace(case, band=band, model="both"))
    assert res.gas is not None and res.band is not None
    assert res.gas["critical_junction"].gap[0] == pytest.approx(res.band.critical_gap_at_max_pressure[0], rel=1e-12, abs=0)
    sigma = res.band.effective_medium.integrals[0].conductance
    u_e = np.cbrt(12 * case.fluid.viscosity * sigma[sigma > 0].min())
    assert res.gas["effective_medium"].gap[0] == pytest.approx(u_e, rel=1e-12, abs=0)
