import numpy as np
import pytest
from scipy import special
from scipy.integrate import quad

from sealeak.physics import _kernels

Y = [0.0, 1e-6, 0.003, 0.1, 0.5, 0.77, 1.0, 2.345, 4.0, 6.4999, 6.5, 7.0, 9.0]


@pytest.mark.parametrize("y", Y)
def test_k_table_against_quadrature(y):
    f = lambda x: special.erf(x) ** 2 * np.exp(-x * x) / x if x > 0 else 0.0
    ref = quad(f, y, np.inf, epsabs=1e-300, epsrel=1e-13, limit=200)[0]
    assert _kernels.k_function(np.array([y]))[0] == pytest.approx(ref, rel=1e-11, abs=1e-14)


@pytest.mark.parametrize("gamma", [1.0, 0.42, 0.1])
@pytest.mark.parametrize("y", [0.05, 0.8, 3.0])
def test_f_and_its_derivative(gamma, y):
    g = lambda x: (gamma + 3 * (1 - gamma) * special.erf(x) ** 2) * np.exp(-x * x) / x
    ref = quad(g, y, np.inf, epsabs=0, epsrel=1e-13)[0]
    assert _kernels.f_function(np.array([y]), gamma)[0] == pytest.approx(ref, rel=1e-11, abs=0)
    assert _kernels.f_derivative(np.array([y]), gamma)[0] == pytest.approx(-g(y), rel=1e-14, abs=0)
