"""Checks of cluster labelling, spanning and the percolation threshold."""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest

from sealeak.errors import InputError
from sealeak.numerics import critical_constriction, label_clusters, percolation_threshold, solve_contact, spanning_mask, spans
from sealeak.numerics.synthesis import synthesize
from sealeak.physics.spectrum import PowerSpectrum

P_C_SQUARE = 0.592746  # site percolation, square lattice (Newman & Ziff, PRL 85 (2000) 4104)


def test_spans_only_through_the_periodic_seam() -> None:
    m = np.zeros((6, 6), dtype=bool)
    m[0:3, 5] = True  # inlet at the right edge, down to row 2
    m[2:6, 0] = True  # continues at the left edge (across the seam) down to the outlet
    assert spans(m)
    assert not spans(m, periodic_axis=None)
    labels, count = label_clusters(m)
    assert count == 1 and (labels[m] == 1).all() and (labels[~m] == 0).all()
    assert label_clusters(m, periodic_axis=None)[1] == 2
    assert spanning_mask(m).sum() == m.sum()
    assert not spans(np.zeros((4, 4), dtype=bool))


def _bfs_count(m: np.ndarray) -> tuple[int, set[int]]:
    """Independent reference: breadth-first search with periodic y neighbours (pure Python)."""
    n0, n1 = m.shape
    seen = np.zeros_like(m, dtype=bool)
    count, spanning = 0, set()
    for i in range(n0):
        for j in range(n1):
            if m[i, j] and not seen[i, j]:
                count += 1
                rows = set()
                todo = deque([(i, j)])
                seen[i, j] = True
                while todo:
                    a, b = todo.popleft()
                    rows.add(a)
                    for da, db in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                        x, y = a + da, (b + db) % n1
                        if 0 <= x < n0 and m[x, y] and not seen[x, y]:
                            seen[x, y] = True
                            todo.append((x, y))
                if 0 in rows and n0 - 1 in rows:
                    spanning.add(count)
    return count, spanning


@pytest.mark.parametrize("seed", range(6))
def test_labels_match_breadth_first_search(seed: int) -> None:
    rng = np.random.default_rng(seed)
    m = rng.random((23, 17)) < 0.55
    count, spanning = _bfs_count(m)
    labels, k = label_clusters(m)
    assert k == count
    assert sorted(np.unique(labels)) == list(range(count + 1))
    assert spans(m) == bool(spanning)


def test_critical_constriction_of_two_channels() -> None:
    """Two channels across a wall: the wider one's narrowest gap (3) decides, not the narrower one's (1)."""
    gap = np.zeros((5, 7))
    gap[:, 1] = [5.0, 1.0, 6.0, 6.0, 5.0]
    gap[:, 4] = [4.0, 4.0, 3.0, 8.0, 4.0]
    fluid = gap > 0
    assert critical_constriction(gap, fluid) == 3.0
    gap[2, 4] = 0.5  # now the other channel is the wider one
    assert critical_constriction(gap, gap > 0) == 1.0
    fluid[3, :] = False  # a wall of contact across: no path
    assert math.isnan(critical_constriction(gap, fluid))


@pytest.mark.parametrize("seed", range(4))
def test_critical_constriction_matches_a_search_over_every_gap(seed: int) -> None:
    """The largest h at which the cells with gap >= h still span, found by breadth-first search at every value."""
    rng = np.random.default_rng(seed)
    gap = rng.random((19, 13))
    fluid = rng.random((19, 13)) < 0.8
    want = next((h for h in np.unique(gap[fluid])[::-1] if _bfs_count(fluid & (gap >= h))[1]), float("nan"))
    got = critical_constriction(gap, fluid)
    assert got == want or (math.isnan(got) and math.isnan(want))


def test_site_percolation_threshold_square_lattice() -> None:
    """Per-sample thresholds (occupied sets are nested in p, so bisection on the sorted uniforms is
    exact) average to p_c within 3 standard errors plus the finite-size shift ~ L^(-1/ν), ν = 4/3."""
    L, samples = 128, 24
    rng = np.random.default_rng(2024)
    thresholds = []
    for _ in range(samples):
        u = rng.random((L, L))
        values = np.sort(u.ravel())
        lo, hi = 0, values.size - 1  # spans with values[hi] included, not with values[lo]
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if spans(u <= values[mid]):
                hi = mid
            else:
                lo = mid
        thresholds.append(values[hi])
    t = np.array(thresholds)
    width = L ** (-3.0 / 4.0)  # finite-size width of the transition
    sem = t.std(ddof=1) / math.sqrt(samples)
    assert abs(t.mean() - P_C_SQUARE) <= 3 * sem + 0.5 * width
    assert 0.2 * width < t.std(ddof=1) < 2.0 * width


def test_percolation_threshold_of_a_contact() -> None:
    n, L, e_star = 128, 1e-3, 1e6
    q0 = 2 * np.pi / L
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * q0, q_cutoff=16 * q0, q_lowest=q0, h_rms=1e-6)
    h = synthesize(sp, n, L, seed=4)
    scale = e_star * sp.slope_rms
    res = percolation_threshold(h, L, e_star, p_lo=0.02 * scale, p_hi=0.5 * scale, rel_tol=1e-3)
    assert res.pressure_spanning < res.pressure_blocked
    assert (res.pressure_blocked - res.pressure_spanning) / res.pressure_blocked <= 1e-3
    a = solve_contact(h, L, e_star, res.pressure_spanning)
    b = solve_contact(h, L, e_star, res.pressure_blocked)
    assert spans(~a.contact) and not spans(~b.contact)
    assert a.contact_area == pytest.approx(res.area_spanning, abs=2.0 / n**2)
    # numerically exact studies put the threshold near A/A0 = 0.42 (Wang & Müser 2020); a
    # single 128² realisation scatters widely around it
    assert 0.25 < res.contact_area < 0.65
    with pytest.raises(InputError, match="p_hi"):
        percolation_threshold(h, L, e_star, p_lo=0.02 * scale, p_hi=0.03 * scale)
