"""O-ring contact mechanics and the Shore A hardness (docs/theory.md §10.2).

Every expected value is computed here from the published formula (Hertz line contact between two
plates, Lindley's O-ring relations, the durometer's spring law) or from an independent relation,
never copied from the module's output.
"""

import math

import numpy as np
import pytest
from scipy import integrate, special

from sealeak.errors import InputError
from sealeak.physics.oring import (
    HERTZ_UPTO,
    LINDLEY_CHECKED_UPTO,
    LINDLEY_FROM,
    MAX_COMPRESSION,
    compression_from_groove_depth,
    oring_contact,
    shore_a_warnings,
    youngs_modulus_from_shore_a,
)

D = 2.62e-3  # m, a common O-ring cross-section
E = 5.0e6  # Pa


@pytest.mark.parametrize("eps", [0.002, 0.01, 0.03, 0.1, 0.2, 0.3, 0.45])
@pytest.mark.parametrize("nu", [0.5, 0.3])
def test_profile_integrates_to_the_force(eps, nu):
    c = oring_contact(D, E, nu, eps)
    prof = c.profile(0)
    w = float(c.contact_width[0])
    carried, _ = integrate.quad(lambda x: float(prof.at(x)), 0.0, w, epsabs=0.0, epsrel=1e-11, limit=200)
    assert carried == pytest.approx(float(c.force_per_length[0]), rel=1e-8)
    assert prof.width == pytest.approx(w, rel=1e-14, abs=0)
    assert float(c.mean_pressure[0]) == pytest.approx(carried / w, rel=1e-8)
    # the semi-ellipse: zero at the edges, p_max in the middle
    assert float(prof.at(0.0)) == 0.0 and float(prof.at(w)) == 0.0
    assert float(prof.at(w / 2)) == pytest.approx(float(c.max_pressure[0]), rel=1e-12)


@pytest.mark.parametrize("eps", [1e-4, 0.002, 0.005, HERTZ_UPTO])
@pytest.mark.parametrize("d, e, nu", [(D, E, 0.5), (5.33e-3, 2.0e6, 0.49), (1.0e-3, 10e6, 0.3)])
def test_small_squeeze_is_hertz_between_two_plates(eps, d, e, nu):
    c = oring_contact(d, e, nu, eps)
    f = float(c.force_per_length[0])
    r, e_star = d / 2, e / (1 - nu**2)
    b = math.sqrt(4 * f * r / (math.pi * e_star))  # Hertz line contact half-width
    assert float(c.contact_width[0]) == pytest.approx(2 * b, rel=1e-10, abs=0)
    assert float(c.max_pressure[0]) == pytest.approx(2 * f / (math.pi * b), rel=1e-10)
    # the compression of a cylinder between two rigid plates: δ = (2f/(πE*)) (2 ln(4R/b) - 1) = ε d
    delta = 2 * f / (math.pi * e_star) * (2 * math.log(4 * r / b) - 1)
    assert delta == pytest.approx(eps * d, rel=1e-10, abs=0)
    assert b / r < 0.08  # narrow against the radius: Hertz's half-space assumption holds
    assert c.regime == ("Hertz",)


def test_hertz_numbers_by_hand():
    # ε = 1 %, d = 2 mm, E = 3 MPa, ν = 0.5 (E* = 4 MPa). With φ = f/(E* d) = 0.00226 the half-width is
    # b = d sqrt(2φ/π) = 0.0758 mm and the approach (2φ/π)(ln(2π/φ) - 1) d = 0.001439 × 6.930 × 2 mm = 0.0199 mm ≈ ε d.
    c = oring_contact(2e-3, 3e6, 0.5, 0.01)
    assert float(c.force_per_length[0]) == pytest.approx(0.00226 * 4e6 * 2e-3, rel=5e-3)
    assert float(c.contact_width[0]) == pytest.approx(2 * 0.0758e-3, rel=5e-3)


@pytest.mark.parametrize("eps", [LINDLEY_FROM, 0.15, 0.2, 0.25, LINDLEY_CHECKED_UPTO, 0.4])
@pytest.mark.parametrize("d", [1.78e-3, D, 6.99e-3])
def test_larger_squeeze_is_lindley(eps, d):
    c = oring_contact(d, E, 0.5, eps)
    f = E * d * (1.25 * eps**1.5 + 50 * eps**6)  # Lindley (1967), force per unit length of seal line
    w = d * math.sqrt(6 * eps / math.pi)  # Lindley's contact width
    assert float(c.force_per_length[0]) == pytest.approx(f, rel=1e-12)
    assert float(c.contact_width[0]) == pytest.approx(w, rel=1e-12, abs=0)
    assert float(c.max_pressure[0]) == pytest.approx(4 * f / (math.pi * w), rel=1e-12)
    assert c.regime == ("Lindley",)


def test_lindley_numbers_by_hand():
    # d = 2.62 mm, E = 5 MPa, ε = 20 %: 1.25 × 0.2^1.5 = 0.1118034, 50 × 0.2^6 = 0.0032,
    # f = 5e6 × 2.62e-3 × 0.1150034 = 1506.5 N/m; w = 2.62 mm × sqrt(1.2/π) = 2.62 × 0.618039 = 1.6193 mm;
    # p_max = 4 × 1506.5/(π × 1.6193e-3) = 1.1846 MPa.
    c = oring_contact(2.62e-3, 5e6, 0.5, 0.2)
    assert float(c.force_per_length[0]) == pytest.approx(1506.5, rel=1e-4)
    assert float(c.contact_width[0]) == pytest.approx(1.6193e-3, rel=1e-4)
    assert float(c.max_pressure[0]) == pytest.approx(1.1846e6, rel=1e-4)


def test_other_poisson_ratio_scales_lindley_by_the_plane_strain_modulus():
    eps = [0.05, 0.2]
    inc = oring_contact(D, E, 0.5, eps)
    soft = oring_contact(D, E, 0.3, eps)
    ratio = 0.75 / (1 - 0.3**2)  # (3/4) E* / E
    np.testing.assert_allclose(soft.force_per_length / inc.force_per_length, ratio, rtol=1e-12)
    np.testing.assert_allclose(soft.contact_width, inc.contact_width, rtol=1e-12)
    assert any("incompressible" in w for w in soft.warnings)
    assert not any("incompressible" in w for w in inc.warnings)


@pytest.mark.parametrize("boundary", [HERTZ_UPTO, LINDLEY_FROM])
@pytest.mark.parametrize("nu", [0.5, 0.3])
def test_force_width_and_peak_are_continuous_at_the_regime_boundaries(boundary, nu):
    c = oring_contact(D, E, nu, [boundary * (1 - 1e-9), boundary, boundary * (1 + 1e-9)])
    for q in (c.force_per_length, c.contact_width, c.max_pressure):
        assert abs(q[2] / q[0] - 1) < 1e-7


def test_force_width_and_peak_rise_with_the_compression():
    eps = np.geomspace(1e-4, MAX_COMPRESSION * (1 - 1e-9), 3000)
    c = oring_contact(D, E, 0.5, eps)
    for q in (c.force_per_length, c.contact_width, c.max_pressure, c.mean_pressure):
        assert np.all(np.diff(q) > 0)
    order = {"Hertz": 0, "Hertz-Lindley": 1, "Lindley": 2}
    ranks = [order[r] for r in c.regime]
    assert ranks == sorted(ranks) and set(ranks) == {0, 1, 2}
    assert np.all(c.contact_width < D)  # the band stays narrower than the cross-section


def test_force_scales_with_modulus_and_diameter():
    # f/(E* d) and w/d depend on ε alone: both relations are dimensionless in that form
    a = oring_contact(D, E, 0.5, [0.005, 0.05, 0.2])
    b = oring_contact(3 * D, 2 * E, 0.5, [0.005, 0.05, 0.2])
    np.testing.assert_allclose(b.force_per_length / a.force_per_length, 6.0, rtol=1e-12)
    np.testing.assert_allclose(b.contact_width / a.contact_width, 3.0, rtol=1e-12)
    np.testing.assert_allclose(b.max_pressure / a.max_pressure, 2.0, rtol=1e-12)


def test_warns_between_the_checked_range_and_the_hard_limit():
    assert oring_contact(D, E, 0.5, [0.1, 0.2, LINDLEY_CHECKED_UPTO]).warnings == ()
    c = oring_contact(D, E, 0.5, [0.2, 0.35, 0.45])
    assert len(c.warnings) == 1
    assert "35 %" in c.warnings[0] and "45 %" in c.warnings[0] and "20 %" not in c.warnings[0]
    assert np.all(np.isfinite(c.force_per_length))


@pytest.mark.parametrize("bad", [0.0, -0.1, MAX_COMPRESSION, 0.7, 1.0, float("nan"), float("inf")])
def test_bad_compression_is_refused_naming_it(bad):
    with pytest.raises(InputError) as exc:
        oring_contact(D, E, 0.5, bad)
    assert exc.value.field == "compression"
    with pytest.raises(InputError) as exc:
        oring_contact(D, E, 0.5, [0.1, 0.2, bad])
    assert exc.value.field == "compression[2]"


@pytest.mark.parametrize("bad", [0.0, -1e-3, float("nan"), float("inf"), "thick"])
def test_bad_cross_section_is_refused_naming_it(bad):
    with pytest.raises(InputError) as exc:
        oring_contact(bad, E, 0.5, 0.2)
    assert exc.value.field == "cross_section_diameter"


@pytest.mark.parametrize("e, nu, field", [(0.0, 0.5, "youngs_modulus"), (-1e6, 0.5, "youngs_modulus"),
                                          (float("nan"), 0.5, "youngs_modulus"), (E, 0.6, "poisson_ratio"),
                                          (E, -1.0, "poisson_ratio")])
def test_bad_rubber_is_refused_naming_it(e, nu, field):
    with pytest.raises(InputError) as exc:
        oring_contact(D, e, nu, 0.2)
    assert exc.value.field == field


@pytest.mark.parametrize("eps", [0.01, 0.15, 0.3, 0.45])
def test_groove_depth_gives_the_compression(eps):
    depth = D * (1 - eps)
    assert compression_from_groove_depth(D, depth)[0] == pytest.approx(eps, rel=1e-12, abs=0)
    np.testing.assert_allclose(compression_from_groove_depth(D, [depth, D * 0.8]), [eps, 0.2], rtol=1e-12)
    a = oring_contact(D, E, 0.5, compression_from_groove_depth(D, depth))
    b = oring_contact(D, E, 0.5, eps)
    np.testing.assert_allclose(a.force_per_length, b.force_per_length, rtol=1e-12)


@pytest.mark.parametrize("bad, words", [(D, "not squeezed"), (1.2 * D, "not squeezed"), (0.0, "> 0"), (-1e-3, "> 0"),
                                        (float("nan"), "> 0"), (0.5 * D, "50 %"), (0.3 * D, "50 %")])
def test_bad_groove_depth_is_refused_naming_it(bad, words):
    with pytest.raises(InputError) as exc:
        compression_from_groove_depth(D, bad)
    assert exc.value.field == "groove_depth" and words in str(exc.value)
    with pytest.raises(InputError) as exc:
        compression_from_groove_depth(D, [0.8 * D, bad])
    assert exc.value.field == "groove_depth[1]"


# ---------------------------------------------------------------- Shore A

def test_gent_is_the_durometer_spring_over_a_truncated_cone_indentation():
    """E h / F is one indenter constant at every hardness, between the flat-punch bounds of the indenter's tip and base.

    ASTM D2240 type A: spring force F = 0.550 + 0.075 S N, indentation h = 2.54 mm (100 - S)/100
    (the reading falls from 100 at no indentation). A rigid flat punch of radius a on an incompressible
    half-space needs F = 2 a E* h = (8/3) a E h; the type A indenter is a 35° truncated cone with a
    0.79 mm tip, 1.18 mm in radius where it meets the surface at full travel, so C = F/(E h) lies between
    (8/3)(0.395 mm) and (8/3)(1.18 mm).
    """
    s = np.arange(20.0, 96.0, 5.0)
    e = np.array([youngs_modulus_from_shore_a(v) for v in s])
    force = 0.550 + 0.075 * s
    h = 2.54e-3 * (100 - s) / 100
    c = force / (e * h)
    assert np.ptp(c) / c.mean() < 0.01
    assert 8 / 3 * 0.395e-3 < c.mean() < 8 / 3 * 1.18e-3


@pytest.mark.parametrize("shore", [40, 50, 60, 70, 80, 85])
def test_gent_agrees_with_the_finite_element_hardness_relation(shore):
    # Qi, Joyce & Boyce, Rubber Chem. Technol. 76 (2003) 419: S = 100 erf(3.186e-4 sqrt(E/Pa)) from
    # finite-element simulations of the type A durometer on neo-Hookean rubber. A hardness reading is
    # good to about ±5 points (rubber specifications give ±5), so that is the tolerance.
    e = youngs_modulus_from_shore_a(shore)
    assert 100 * special.erf(3.186e-4 * math.sqrt(e)) == pytest.approx(shore, abs=5)


def test_gent_rises_without_bound_towards_100():
    e = [youngs_modulus_from_shore_a(s) for s in (10, 30, 50, 70, 90, 99, 99.9)]
    assert all(b > a for a, b in zip(e, e[1:]))
    assert e[-1] > 100 * e[2]
    assert 1e6 < youngs_modulus_from_shore_a(50) < 5e6  # a soft rubber: a few MPa


@pytest.mark.parametrize("bad", [0, 100, -5.0, 120.0, float("nan"), float("inf"), True, "70", None])
def test_bad_shore_a_is_refused_naming_it(bad):
    with pytest.raises(InputError) as exc:
        youngs_modulus_from_shore_a(bad)
    assert exc.value.field == "shore_a"


@pytest.mark.parametrize("shore, warned", [(20, True), (39, True), (40, False), (70, False), (90, False), (95, True)])
def test_shore_a_outside_the_supported_range_is_warned(shore, warned):
    assert bool(shore_a_warnings(shore)) is warned
    assert youngs_modulus_from_shore_a(shore) > 0
