"""The fast effective-medium evaluation against straightforward evaluations of the same equations.

The separation integrals, the gap distribution's discretisation and the Bruggeman solve are written out
here plainly (scipy.special.exp1, the spectrum's generic inverse moment, plain mixture sums, bisection,
brentq), on the same quadrature rules, so any difference is the fast code's own error
(docs/theory.md §2.9, §5.5).
"""

import numpy as np
import pytest
from scipy import integrate, optimize, special

from sealeak import PowerSpectrum
from sealeak.cases import example_path, load_cases
from sealeak.physics import _kernels
from sealeak.physics import contact as contact_module
from sealeak.physics.contact import PerssonContact, contact_modulus
from sealeak.physics.effective_medium import _Mixture, discretise, effective_medium
from sealeak.physics.gaps import GapDistribution, folded_normal_cdf, gap_distribution

E_STAR = contact_modulus(2.3e6, 0.5)
Q0 = 2 * np.pi / 5e-3
ETA = 1e-3


def self_affine(gamma=1.0):
    s = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=9.1e3, q_cutoff=2 * np.pi / 20e-6, q_lowest=Q0, h_rms=44e-6)
    return PerssonContact(s, E_STAR, Q0, gamma)


def tabulated():
    """30 nodes with curvature in log-log: every panel of the separation integrals sits on a different segment."""
    q = np.geomspace(1e3, 3e5, 30)
    c = 1e-17 / (1 + (q / 1e4) ** 2) ** 1.6 * np.exp(-((np.log(q / 3e4)) ** 2) / 8)
    return PerssonContact(PowerSpectrum.from_arrays(q, c), E_STAR, 2 * np.pi / 4e-3)


def steep_segment():
    """C ∝ q^-4 on the first segment: e = 3 + 1 + β = 0 exactly, the inverse moment's logarithmic case."""
    q = np.array([2e3, 4e3, 4e5])
    c = np.array([1.6e-17, 1.6e-17 / 16, 1.6e-17 / 16 * 1e-6])
    spectrum = PowerSpectrum.from_arrays(q, c)
    assert 4.0 + spectrum.exponents[0] == 0.0
    return PerssonContact(spectrum, 1e7, 2 * np.pi / 2e-3)


def hurst_06():
    s = PowerSpectrum.self_affine(hurst=0.6, q_rolloff=2e4, q_cutoff=1e7, q_lowest=5e3, h_rms=2e-6)
    return PerssonContact(s, 1e7, 2 * np.pi / 2e-3)


def reference_experiment():
    return load_cases(example_path("reference-experiment"))[0].contact()


CONTACTS = {"reference experiment": (reference_experiment, [1e4, 3.9e4, 1.5e5]),
            "self-affine": (self_affine, [1.5e4, 6e4, 2.5e5]),
            "self-affine, gamma 0.42": (lambda: self_affine(0.42), [2e4, 1.2e5]),
            "tabulated": (tabulated, [5e3, 4e4]),
            "steep segment": (steep_segment, [3e4, 3e5]),
            "H = 0.6": (hurst_06, [3e4, 1e6])}


# ---------------------------------------------------------------------------------------------- special functions
def test_exp1_against_scipy():
    x = np.concatenate([np.geomspace(1e-300, 1e-2, 2000), np.geomspace(1e-2, 700.0, 200_000), np.geomspace(700.0, 800.0, 500),
                        np.nextafter(1e-2, [0.0, 1.0]), np.nextafter(700.0, [0.0, 1e3]), [1e-2, 700.0]])
    ref = special.exp1(x)
    got = _kernels.exp1(x)
    normal = ref >= np.finfo(float).tiny
    assert np.max(np.abs(got[normal] / ref[normal] - 1)) < 1e-14
    # beyond x ≈ 708 E1 is subnormal (few significant bits), beyond ≈ 745 it underflows to 0, as scipy's
    assert np.max(np.abs(got[~normal] - ref[~normal])) < 1e-315
    assert np.array_equal(got == 0, ref == 0)
    # ln x and e^-x given by the caller: the same values
    assert np.array_equal(_kernels.exp1(x, np.log(x), np.exp(-x)), got)
    assert _kernels.exp1(np.float64(2.0)) == pytest.approx(special.exp1(2.0), rel=1e-15, abs=0)


@pytest.mark.parametrize("gamma", [1.0, 0.42, 0.1])
def test_f_and_slope_against_their_definitions(gamma):
    y = np.geomspace(1e-4, 30.0, 3000)
    f, p = _kernels.f_and_slope(y * y, 2 * np.log(y), gamma)
    k = _kernels.k_function(y)  # (checked against quadrature in test_kernels.py)
    f_ref = 0.5 * gamma * special.exp1(y * y) + 3 * (1 - gamma) * k
    p_ref = (gamma + 3 * (1 - gamma) * special.erf(y) ** 2) * np.exp(-y * y)  # -y F'(y)
    live = f_ref > 1e-300
    assert np.max(np.abs(f[live] / f_ref[live] - 1)) < 1e-14
    assert np.max(np.abs(p[live] / p_ref[live] - 1)) < 1e-14


# ---------------------------------------------------------------------------------------------- separation integrals
def plain_panel_sums(contact, edges, active, m_lo, kappa, d, pz):
    """ū and ū' on the same panels, point by point with scipy's E1 and the spectrum's generic inverse moment."""
    spec = contact.spectrum
    xg, wg = np.polynomial.legendre.leggauss(contact.order)
    ubar = np.zeros(edges.shape[0])
    dubar = np.zeros(edges.shape[0])
    for i in np.flatnonzero(active):
        a, b = edges[i, :-1], edges[i, 1:]
        keep = b > a
        half = 0.5 * (b - a)[keep]
        s = (a[keep] + half)[:, None] + half[:, None] * xg
        w = half[:, None] * wg
        t = np.exp(s)
        q = spec.inverse_cumulative_moment(3, t + m_lo[i])
        y = kappa[i] / np.sqrt(t)
        f = 0.5 * contact.gamma * special.exp1(y * y) + 3 * (1 - contact.gamma) * _kernels.k_function(y)
        fp = -(contact.gamma + 3 * (1 - contact.gamma) * special.erf(y) ** 2) * np.exp(-y * y) / y
        ubar[i] = np.sum(w * np.sqrt(t) * f / q)
        dubar[i] = np.sum(w * (d[i] * (f + y * fp) / (2 * q * np.sqrt(t)) + pz[i] * fp / q))
    return ubar, dubar


@pytest.mark.parametrize("name", sorted(CONTACTS))
def test_separation_integrals_against_plain_evaluation(name, monkeypatch):
    make, pressures = CONTACTS[name]
    contact = make()
    calls = []
    fast = PerssonContact._panel_sums

    def spy(self, *args):
        out = fast(self, *args)
        calls.append((args, out))
        return out

    monkeypatch.setattr(PerssonContact, "_panel_sums", spy)
    zeta = np.concatenate([[1.0], np.geomspace(1.0001, contact.zeta_max * 0.9999, 60), [contact.zeta_max]])
    for p0 in pressures:
        contact.u1(zeta, p0)
    assert calls
    for (edges, active, m_lo, kappa, d, pz, *_), (ubar, dubar) in calls:
        ref_u, ref_d = plain_panel_sums(contact, edges, active, m_lo, kappa, d, pz)
        assert np.allclose(ubar, ref_u, rtol=1e-13, atol=1e-15 * np.max(np.abs(ref_u)))
        assert np.allclose(dubar, ref_d, rtol=1e-13, atol=1e-15 * np.max(np.abs(ref_d)))


def test_panel_blocks_cover_every_panel_once(monkeypatch):
    contact = self_affine()
    zeta = np.geomspace(1.0, contact.zeta_max, 300)
    want = contact.u1(zeta, 6e4)
    monkeypatch.setattr(contact_module, "_BLOCK", 7)  # many blocks, the last one partial
    assert np.allclose(contact.u1(zeta, 6e4), want, rtol=1e-14, atol=0)


# ---------------------------------------------------------------------------------------------- the mixture P(u)
def plain_density(dist: GapDistribution, i, u):
    """The continuous density of row i at u: Σ W [φ((u-c)/h) + φ((u+c)/h)]/h, terms beyond √80 h left out."""
    live = (dist.weights[i] > 0) & (dist.widths[i] > 0)
    w, c, h = dist.weights[i, live], dist.centres[i, live], dist.widths[i, live]
    z = ((u[:, None] - c) / h) ** 2
    zm = ((u[:, None] + c) / h) ** 2
    terms = np.where(z < 80, np.exp(-0.5 * z), 0.0) + np.where(zm < 80, np.exp(-0.5 * zm), 0.0)
    return terms @ (w / (np.sqrt(2 * np.pi) * h))


def plain_cdf(dist: GapDistribution, i, u):
    return np.sum(dist.weights[i] * folded_normal_cdf(np.atleast_1d(u)[:, None], dist.centres[i], dist.widths[i]), axis=1)


def plain_tail(dist: GapDistribution, i, u):
    """1 - CDF at u, as Σ W P(|X| > u) (mass - CDF would leave only rounding noise at 1e-13 of the mass)."""
    live = dist.weights[i] > 0
    w, c, h = dist.weights[i, live], dist.centres[i, live], dist.widths[i, live]
    hs = np.where(h > 0, h, 1.0)
    return np.sum(w * np.where(h > 0, special.ndtr((c - u) / hs) + special.ndtr((-u - c) / hs), c > u))


@pytest.fixture(scope="module", params=sorted(CONTACTS))
def distribution(request):
    make, pressures = CONTACTS[request.param]
    return gap_distribution(make(), pressures)


def test_mixture_density_and_cdf_against_plain_sums(distribution):
    gaps, _ = discretise(distribution)
    mix = _Mixture(distribution)
    for i in range(len(distribution)):
        u = gaps[i]
        ref = plain_density(distribution, i, u)
        got = mix.density_on(i, u)
        assert np.array_equal(ref == 0, got == 0)
        assert np.max(np.abs(got - ref) / np.where(ref > 0, ref, 1.0)) < 1e-13
        # the plain CDF is a difference of two normal CDFs: absolute precision ~1e-16 per component
        assert np.max(np.abs(mix.cdf_on(i, u) - plain_cdf(distribution, i, u))) < 1e-14


def test_cut_points_are_the_quantiles(distribution):
    """u_lo: CDF = 1e-10 of the continuous mass; u_hi: 1 - CDF = 1e-13 of it (docs/theory.md §5.5)."""
    gaps, _ = discretise(distribution)
    d = distribution
    for i in np.flatnonzero(d.weights.sum(axis=1) > 0):
        mass = d.weights[i].sum()
        u_lo, u_hi = gaps[i, 0], gaps[i, -1]
        # the CDF up to u_lo by quadrature of the density (no cancellation), ln u substitution
        below = integrate.quad(lambda x: np.exp(x) * plain_density(d, i, np.array([np.exp(x)]))[0], np.log(u_lo) - 60,
                               np.log(u_lo), epsabs=0, epsrel=1e-12, limit=200)[0]
        # (the cut is the root of the fast CDF; this quadrature of the plain density differs from it by up to 4.7e-4 at
        # 1e-10 of the mass, which moves no leak rate)
        assert below == pytest.approx(1e-10 * mass, rel=2e-3, abs=0)
        # 1 - CDF without cancellation; the root may sit on a step of the comb of narrow components far out,
        # so it is checked as a crossing within 1e-11 either side
        assert plain_tail(d, i, u_hi * (1 - 1e-11)) >= 1e-13 * mass * (1 - 1e-9)
        assert plain_tail(d, i, u_hi * (1 + 1e-11)) <= 1e-13 * mass * (1 + 1e-9)


# ---------------------------------------------------------------------------------------------- the whole chain
def plain_discretise(dist: GapDistribution, panel_width=0.25, order=8):
    """docs/theory.md §5.5 written out: bisection for the cut points, plain sums for density, CDF and upper tail."""
    rows = len(dist)
    mass = dist.weights.sum(axis=1)
    scale = np.maximum(dist.mean, 1e-200)
    top = np.maximum(np.max(np.where(dist.weights > 0, dist.centres + 12 * dist.widths, 0.0), axis=1), scale)
    u_lo, u_hi = np.empty(rows), np.empty(rows)
    for i in range(rows):
        a, b = np.log(scale[i] * 1e-30), np.log(top[i])
        for _ in range(100):
            m = 0.5 * (a + b)
            a, b = (m, b) if plain_cdf(dist, i, np.exp(m))[0] < 1e-10 * mass[i] else (a, m)
        u_lo[i] = np.exp(0.5 * (a + b))
        a, b = np.log(scale[i] * 1e-30), np.log(10 * top[i])
        for _ in range(100):
            m = 0.5 * (a + b)
            a, b = (m, b) if plain_tail(dist, i, np.exp(m)) > 1e-13 * mass[i] else (a, m)
        u_hi[i] = np.exp(0.5 * (a + b))
    u_hi = np.maximum(u_hi, u_lo * 1.0001)
    span = np.log(u_hi / u_lo)
    xg, wg = np.polynomial.legendre.leggauss(order)
    gaps, weights = [], []
    for i in range(rows):
        n_pan = int(np.ceil(span[i] / panel_width))  # each row its own panels
        edges = np.log(u_lo[i]) + span[i] * np.arange(n_pan + 1) / n_pan
        half = 0.5 * np.diff(edges)
        u = np.exp((edges[:-1] + half)[:, None] + half[:, None] * xg)
        w = half[:, None] * wg * u * plain_density(dist, i, u.ravel()).reshape(u.shape)
        cdf = plain_cdf(dist, i, np.exp(edges))
        exact = np.diff(cdf)
        approx = w.sum(axis=1)
        for j in range(n_pan):
            if 0.5 * exact[j] < approx[j] < 2 * exact[j]:
                w[j] *= exact[j] / approx[j]
            else:
                w[j] = 0.0
                w[j, order // 2] = max(exact[j], 0.0)
        gaps.append(np.concatenate([[u_lo[i]], u.ravel(), [u_hi[i]]]))
        weights.append(np.concatenate([[cdf[0]], w.ravel(), [max(mass[i] - cdf[-1], 0.0)]]))
    return gaps, weights  # (rows of their own lengths)


def plain_bruggeman(gaps, weights, contact_fraction):
    """σ_eff of each row: brentq on 2c + Σ W 2σ/(σ + u³/12η) = 1 in ln σ; 0 when c >= 1/2."""
    out = []
    for u, w, c in zip(gaps, weights, contact_fraction):
        total = c + w.sum()
        w, c = w / total, c / total
        if 2 * c >= 1:
            out.append(0.0)
            continue
        local = u**3 / (12 * ETA)
        g = lambda x: 2 * c + np.sum(w * 2 / (1 + local / np.exp(x))) - 1
        out.append(np.exp(optimize.brentq(g, np.log(local.min()) - 60, np.log(local.max()) + 60, xtol=1e-14, rtol=1e-15)))
    return np.array(out)


@pytest.mark.parametrize("name", sorted(CONTACTS))
def test_effective_medium_against_plain_evaluation(name):
    """σ_eff to 1e-11: the module's Newton iteration stops at |1 - g| < 1e-12, which leaves σ_eff a few 1e-12 from
    brentq's root; rounding in the plain sums (the CDF as a difference of normal CDFs) adds ~1e-14."""
    make, pressures = CONTACTS[name]
    contact = make()
    res = effective_medium(contact, squeeze_pressure=pressures, pressure_difference=1e4, viscosity=ETA, aspect_ratio=1.0)
    gaps, weights = plain_discretise(res.distribution)
    want = plain_bruggeman(gaps, weights, res.distribution.contact_fraction)
    assert np.array_equal(want > 0, res.percolates)
    assert np.allclose(res.effective_conductivity, want, rtol=1e-11, atol=0)


def test_pressures_are_evaluated_independently():
    """A sweep gives each pressure the result it gets alone: its panels are its own, and only the order of the sums in
    the Bruggeman equation differs (rows with fewer panels than the widest are padded with zero weights)."""
    contact = self_affine()
    p0 = np.array([6e4, 1.5e4, 2.5e5, 6e4, 3e5])
    together = effective_medium(contact, squeeze_pressure=p0, pressure_difference=1e4, viscosity=ETA, aspect_ratio=1.0)
    for i, p in enumerate(p0):
        alone = effective_medium(contact, squeeze_pressure=[p], pressure_difference=1e4, viscosity=ETA, aspect_ratio=1.0)
        assert together.effective_conductivity[i] == pytest.approx(alone.effective_conductivity[0], rel=1e-11, abs=0)
        assert together.distribution.centres[np.searchsorted(together.distribution.squeeze_pressure, p)] == \
            pytest.approx(alone.distribution.centres[0], rel=1e-14, abs=1e-300)
