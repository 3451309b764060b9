"""The critical-junction leak rate: the Poiseuille formula through the critical constriction, its
linearity in ΔP and α, its trends with the squeeze pressure and the percolation threshold, the ring
geometry, and the refusal of invalid arguments (Lorenz & Persson 2009)."""

import numpy as np
import pytest

from sealeak import InputError, PowerSpectrum
from sealeak.physics.contact import PerssonContact, contact_modulus
from sealeak.physics.critical_junction import critical_junction
from sealeak.physics.seal import Seal

Q0 = 2 * np.pi / 5e-3


@pytest.fixture(scope="module")
def contact():
    s = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=9.1e3, q_cutoff=3.14e5, q_lowest=Q0, h_rms=44e-6)
    return PerssonContact(s, contact_modulus(2.3e6, 0.5), Q0, gamma=0.42)


def run(contact, **kw):
    args = dict(squeeze_pressure=np.geomspace(2e4, 2e5, 12), pressure_difference=1e4, viscosity=1e-3,
                aspect_ratio=22.0, alpha=0.2)
    args.update(kw)
    return critical_junction(contact, **args)


def test_leak_rate_is_the_poiseuille_formula(contact):
    r = run(contact)
    zc, _ = contact.zeta_at_area(0.4, r.squeeze_pressure)
    uc = contact.u1(zc, r.squeeze_pressure)
    assert np.allclose(r.critical_gap, uc, rtol=1e-14)
    assert np.allclose(r.leak_rate, 0.2 * 22.0 * uc**3 * 1e4 / (12 * 1e-3), rtol=1e-13)
    assert np.allclose(r.critical_wavelength, 2 * np.pi / (zc * Q0), rtol=1e-14)


def test_linear_in_pressure_difference_and_alpha_inverse_in_viscosity(contact):
    base = run(contact).leak_rate
    assert np.allclose(run(contact, pressure_difference=3e4).leak_rate, 3 * base, rtol=1e-14)
    assert np.allclose(run(contact, alpha=0.7).leak_rate, 3.5 * base, rtol=1e-14)
    assert np.allclose(run(contact, viscosity=2e-3).leak_rate, base / 2, rtol=1e-14)
    assert np.allclose(run(contact, aspect_ratio=11.0).leak_rate, base / 2, rtol=1e-14)


def test_trends_with_squeeze_pressure(contact):
    r = run(contact)
    assert r.percolates.all()
    assert np.all(np.diff(r.critical_gap) < 0)
    assert np.all(np.diff(r.critical_magnification) > 0)
    assert np.all(np.diff(r.leak_rate) < 0)
    # the paper: the critical pore is much wider than high
    assert np.all(r.critical_wavelength > 5 * r.critical_gap)


def test_percolation_threshold_moves_the_junction(contact):
    low = run(contact, percolation_threshold=0.5)
    high = run(contact, percolation_threshold=0.7)
    # a higher p_c means percolation at a smaller contact area -> higher magnification -> thinner gap
    assert np.all(high.critical_magnification > low.critical_magnification)
    assert np.all(high.critical_gap < low.critical_gap)


def test_no_percolation_gives_no_number(contact):
    r = run(contact, squeeze_pressure=[5e4, 5e7])
    assert r.percolates.tolist() == [True, False]
    assert np.isfinite(r.leak_rate[0]) and np.isnan(r.leak_rate[1])
    assert np.isnan(r.critical_gap[1]) and np.isnan(r.critical_magnification[1])
    assert r.contact_area_at_cutoff[1] > 0.4
    assert any("does not percolate" in m or "never percolates" in m for m in r.messages)
    # the resolved roughness is named: a coarse measurement (a scan ending at 0.9 mm) seals for want of finer roughness
    (note,) = [m for m in r.messages if "never percolates" in m]
    cutoff = 2 * np.pi / contact.spectrum.q_max
    assert f"down to 2π/q1 = {cutoff * 1e6:.3g} µm" in note, (note, cutoff)


def test_ring_geometry():
    s = Seal.ring(0.03, 0.04)
    assert s.width == pytest.approx(0.005)
    assert s.aspect_ratio == pytest.approx(np.pi * (0.04 + 0.03) / (0.04 - 0.03))
    assert s.nominal_area == pytest.approx(np.pi * (0.04**2 - 0.03**2) / 4)
    # 3.4 kg on the reference ring
    assert s.squeeze_pressure_from_load(3.4 * 9.80665) == pytest.approx(3.4 * 9.80665 / (np.pi * 7e-4 / 4))
    with pytest.raises(InputError, match="outer_diameter"):
        Seal.ring(0.04, 0.03)


@pytest.mark.parametrize("kw, field", [
    (dict(squeeze_pressure=[]), "squeeze_pressure"),
    (dict(squeeze_pressure=[1e4, -1.0]), "squeeze_pressure[1]"),
    (dict(pressure_difference=-5.0), "pressure_difference"),
    (dict(viscosity=0.0), "viscosity"),
    (dict(alpha=np.nan), "alpha"),
    (dict(percolation_threshold=1.0), "percolation_threshold"),
])
def test_invalid_arguments(contact, kw, field):
    with pytest.raises(InputError) as err:
        run(contact, **kw)
    assert err.value.field == field
