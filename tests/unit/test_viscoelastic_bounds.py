"""A Prony series outside the moduli and times floating-point numbers can carry is one line naming the term, and
every series inside them has a finite, rising creep compliance (docs/theory.md §16.2)."""

import numpy as np
import pytest

from sealeak.errors import InputError
from sealeak.physics.viscoelastic import PRONY_MODULI, PRONY_TIMES, PronySeries


@pytest.mark.parametrize("e_inf, moduli, times, field", [
    (1e6, (1e308, 1e308), (1.0, 2.0), "relaxation.moduli[0]"),
    (1e6, (1e6, 1e6), (1e-300, 1e300), "relaxation.times[0]"),
    (1e-300, (1e6,), (1.0,), "relaxation.equilibrium_modulus"),
    (1e300, (1e6,), (1.0,), "relaxation.equilibrium_modulus"),
])
def test_a_series_beyond_the_ranges_is_refused_naming_the_term(e_inf, moduli, times, field):
    with pytest.raises(InputError) as exc:
        PronySeries(e_inf, moduli, times)
    assert exc.value.field == field and "\n" not in str(exc.value)


@pytest.mark.parametrize("seed", range(5))
def test_every_series_within_the_ranges_has_a_finite_rising_creep_compliance(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 6))
    e_inf = 10 ** rng.uniform(*np.log10(PRONY_MODULI))
    moduli = tuple(10 ** rng.uniform(*np.log10(PRONY_MODULI), n))
    times = tuple(np.geomspace(*PRONY_TIMES, n))  # the widest spread of times
    series = PronySeries(e_inf, moduli, times)
    j = series.creep_compliance(np.array([0.0, 1.0, 1e10, 1e30]))
    assert np.all(np.isfinite(j)) and np.all(np.diff(j) >= 0)
    # J(0) = 1/E(0) and J(∞) = 1/E∞
    assert j[0] == pytest.approx(1 / series.instantaneous_modulus, rel=1e-6, abs=0)  # (up to 1.4e-7)
    assert j[-1] == pytest.approx(1 / e_inf, rel=1e-6, abs=0)
