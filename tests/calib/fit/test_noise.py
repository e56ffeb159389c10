"""Each block's noise comes back from residuals of known noise, the fit's degrees of freedom removed."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.fit import noise
from armtool.model.chain import Chain
from tests.calib.synthetic import make_measured


def test_exact_noise_of_each_block_at_the_truth(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "pose", n=3000, noise_mm=0.2, noise_deg=0.05, seed=1)
    problem = m.measurements.problem(m.model.with_frames(m.L, m.R), m.samples)
    sigma = noise.estimate(problem, m.truth.x, parameters=0)
    assert sigma[0] * 1e3 == pytest.approx(0.2, rel=0.03)
    assert np.degrees(sigma[1]) == pytest.approx(0.05, rel=0.03)


def test_fitted_parameters_take_their_share_of_the_degrees_of_freedom(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "point", n=10, noise_mm=0.2, seed=2)
    problem = m.measurements.problem(m.model.with_frames(m.L, m.R), m.samples)
    plain = noise.estimate(problem, m.truth.x, parameters=0)
    shared = noise.estimate(problem, m.truth.x, parameters=15)
    assert shared[0] == pytest.approx(plain[0] * np.sqrt(30 / 15))


def test_settling_is_relative() -> None:
    assert noise.settled(np.array([1.0, 2.0]), np.array([1.04, 1.95]))
    assert not noise.settled(np.array([1.0, 2.0]), np.array([1.2, 2.0]))
