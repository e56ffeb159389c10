"""Closed-form solution sets: placing solutions within the limits, distinct solutions modulo 2π, and
which of another set's solutions one lacks."""

from __future__ import annotations

import math

import numpy as np
from lxml import etree

from armtool.ik.solutions import DISTINCT_RAD, closed_form_answer, distinct, missing, nearest_first, place, refine
from armtool.model.chain import Chain, chain_from_xml
from tests.ik.robots import COAXIAL_2R, PLANAR_2R

TAU = 2 * math.pi


def planar() -> Chain:
    return chain_from_xml(etree.fromstring(PLANAR_2R))  # revolute, limits ±3 rad


def coaxial() -> Chain:
    return chain_from_xml(etree.fromstring(COAXIAL_2R))  # continuous


def test_place_moves_whole_turns_to_the_seed_then_into_the_limits() -> None:
    chain = planar()
    seed = np.zeros(2)
    placed = place(chain, np.array([[0.5 + TAU, -0.2 - 2 * TAU], [2.9, 0.1]]), seed)
    np.testing.assert_allclose(placed, [[0.5, -0.2], [2.9, 0.1]], atol=1e-12)
    # Nearest the seed is outside ±3 (seed 3, value 3.5): one turn back brings it within.
    np.testing.assert_allclose(place(chain, np.array([[3.5, 0.0]]), np.array([3.0, 0.0])), [[3.5 - TAU, 0.0]])


def test_place_drops_solutions_no_turn_brings_within_the_limits() -> None:
    chain = planar()  # ±3 rad leaves (3, 2π − 3) out of reach of any turn
    assert place(chain, np.array([[3.1, 0.0], [0.0, float("nan")]]), np.zeros(2)).shape == (0, 2)
    # Rounding past a limit is clamped onto it.
    np.testing.assert_allclose(place(chain, np.array([[3.0 + 1e-12, 0.0]]), np.zeros(2)), [[3.0, 0.0]])


def test_place_keeps_a_continuous_joint_nearest_the_seed() -> None:
    chain = coaxial()
    np.testing.assert_allclose(
        place(chain, np.array([[0.1 + 3 * TAU, -7.0]]), np.array([TAU, 0.0])), [[0.1 + TAU, -7.0 + TAU]]
    )


def test_nearest_first() -> None:
    Q = np.array([[1.0, 1.0], [0.1, 0.0], [0.5, 0.5]])
    np.testing.assert_array_equal(nearest_first(Q, np.zeros(2)), Q[[1, 2, 0]])


def test_distinct_is_modulo_whole_turns_at_the_threshold() -> None:
    chain = coaxial()
    q = np.array([0.3, -1.0])
    Q = np.array([q, q + [TAU, -TAU], q + 0.1 * DISTINCT_RAD, q + [10 * DISTINCT_RAD, 0.0], [1.0, 2.0]])
    np.testing.assert_allclose(distinct(chain, Q), [q, q + [10 * DISTINCT_RAD, 0.0], [1.0, 2.0]])
    assert distinct(chain, np.zeros((0, 2))).shape == (0, 2)


def test_missing_counts_the_others_solutions_this_set_lacks() -> None:
    chain = coaxial()
    found = np.array([[0.1, 0.2], [0.3, 0.0]])
    others = np.array([[0.1 + TAU, 0.2], [0.5, -0.2], [0.7, -0.4]])
    assert missing(chain, found, others) == 2
    assert missing(chain, found, others[:1]) == 0
    assert missing(chain, np.zeros((0, 2)), others) == 3
    assert missing(chain, found, np.zeros((0, 2))) == 0


def test_closed_form_answer_claims_exact_solutions_only() -> None:
    chain = planar()
    seed = np.array([0.2, 0.2])
    exact_and_ls = closed_form_answer(chain, "peer", np.array([[1.0, 1.0], [0.3, 0.1]]), [False, True], seed)
    assert exact_and_ls.claimed and not exact_and_ls.reason
    np.testing.assert_allclose(exact_and_ls.q, [0.3, 0.1])  # nearest the seed first, least-squares or not
    assert len(exact_and_ls.solutions) == 2
    ls_only = closed_form_answer(chain, "peer", np.array([[1.0, 1.0]]), [True], seed)
    assert not ls_only.claimed and "least-squares" in ls_only.reason and len(ls_only.solutions) == 1
    outside = closed_form_answer(chain, "peer", np.array([[3.1, 0.0]]), [False], seed)
    assert not outside.claimed and "none within the joint limits" in outside.reason and not outside.solutions
    none = closed_form_answer(chain, "peer", np.zeros((0, 2)), [], seed)
    assert not none.claimed and none.reason == "peer returned no solution"
    np.testing.assert_array_equal(none.q, seed)


def test_refine_moves_an_approximate_solution_onto_the_exact_one() -> None:
    chain = planar()
    q = np.array([0.4, -0.8])
    near = q + [4e-6, -3e-6]  # passes a 1e-5 check, but is 4e-6 rad from the solution it stands for
    refined = refine(chain, np.array([near, q]), chain.fk(q))
    np.testing.assert_allclose(refined, [q, q], atol=1e-12)
    assert distinct(chain, refined).shape == (1, 2) and distinct(chain, np.array([near, q])).shape == (2, 2)
    assert refine(chain, np.zeros((0, 2)), chain.fk(q)).shape == (0, 2)


def test_refine_leaves_a_point_of_a_continuum_where_it_is() -> None:
    chain = coaxial()  # every (a, s - a) reaches the target: the smallest step does not slide along them
    target = chain.fk(np.array([0.3, 0.2]))
    exact = np.array([[0.1, 0.4], [0.25, 0.25]])
    np.testing.assert_allclose(refine(chain, exact, target), exact, atol=1e-12)
    off = exact + [[2e-6, 2e-6]]  # off the continuum: brought back onto it, half each way
    np.testing.assert_allclose(refine(chain, off, target), exact, atol=1e-12)


def test_refine_keeps_a_step_that_would_leave_the_limits_untaken() -> None:
    chain = planar()
    q = np.array([3.0, -0.5])  # at the upper limit of joint 1
    target = chain.fk(q + [2e-6, 0.0])  # the exact solution is just past the limit
    refined = refine(chain, np.array([q]), target)
    np.testing.assert_array_equal(refined, [q])
