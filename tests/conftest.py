"""Shared fixtures: the reference case and a sweep of both models (the laboratory tests use them)."""

from dataclasses import replace

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases, predict, predict_effective_medium


@pytest.fixture(scope="module")
def case():
    return load_cases(example_path("reference-experiment"))[0]


@pytest.fixture(scope="module")
def sweep(case):
    """Unit-α predictions of both models over P0 = 20..400 kPa (Q spans at least three decades in both)."""
    p0 = np.geomspace(2e4, 4e5, 16)
    cj = predict(replace(case, alpha=1.0), squeeze_pressure=p0).leak_rate
    em = predict_effective_medium(case, squeeze_pressure=p0).leak_rate
    return p0, cj, em
