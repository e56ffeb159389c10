"""The identifiability analysis of a rung of the ladder read off the analysis of the whole ladder
is the analysis of the rung itself."""

from __future__ import annotations

import numpy as np

from armtool.calib.fit.crossval import ladder
from armtool.calib.fit.identify import analyse, restricted
from armtool.calib.model.params import Family
from armtool.model.chain import Chain
from tests.calib.synthetic import make_measured


def test_each_rung_restricted_from_the_largest_is_its_own_analysis(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "point", n=40, seed=3)
    problem = m.measurements.problem(m.model, m.samples)
    frames = problem.frame_parameters()
    rungs = ladder([Family.ORIGINS, Family.OFFSETS, Family.GAINS])
    largest = rungs[-1].indices(m.model, frames)
    J = problem.jacobian(np.zeros(m.model.size), largest)
    whole = analyse(m.model, J, largest)
    assert whole.dropped  # a point leaves some parameters unidentifiable: the test compares something
    for rung in rungs:
        indices = rung.indices(m.model, frames)
        own = analyse(m.model, J[:, [largest.index(i) for i in indices]], indices)
        read = restricted(whole, J, largest, indices)
        assert read.kept == own.kept and read.dropped == own.dropped
        assert np.isclose(read.condition_number, own.condition_number)
        assert np.allclose(read.singular_values, own.singular_values)
