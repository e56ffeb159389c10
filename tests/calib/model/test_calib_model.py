"""The measurement model: nominal at zero, corrections composed on the right, both setups."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import Family
from armtool.calib.model.terms.registry import build_terms
from armtool.model.chain import Chain
from tests.calib.conftest import CLEAN_ARM, nominal_model


def test_zero_parameters_give_the_urdf_chain(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    Q = clean_chain.random(np.random.default_rng(0), 20)
    F = model.flange(np.zeros(model.size), Q)
    for q, T in zip(Q, F):
        assert np.allclose(T, clean_chain.fk(q), atol=1e-12)


def test_zero_offset_equals_shifted_reading(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    x = np.zeros(model.size)
    names = [p.name for p in model.params]
    x[names.index("joint3.offset")] = 0.01
    q = clean_chain.mid() + 0.2
    q_shift = q.copy()
    q_shift[2] += 0.01
    assert np.allclose(model.flange(x, q[None])[0], clean_chain.fk(q_shift), atol=1e-12)


def test_origin_correction_composes_on_the_right(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    x = np.zeros(model.size)
    names = [p.name for p in model.params]
    v = np.array([0.001, -0.002, 0.003, 0.01, -0.02, 0.005])
    start = names.index("joint2.origin.tx")
    x[start : start + 6] = v
    q = np.zeros(clean_chain.n)
    expected = np.eye(4)
    for i, j in enumerate(clean_chain.joints):
        expected = expected @ j.origin @ (se3.delta(v) if i == 1 else np.eye(4))
    expected = expected @ clean_chain.tip_offset
    assert np.allclose(model.flange(x, q[None])[0], expected, atol=1e-12)


def test_eye_in_hand_inverts_the_flange(clean_chain: Chain) -> None:
    L = se3.delta(np.array([0.0, 0.0, 0.05, 0.0, 0.0, 0.0]))
    R = se3.delta(np.array([0.5, 0.0, 0.0, 0.0, 0.0, 0.3]))
    model = CalibModel(clean_chain, Setup.EYE_IN_HAND, L, R)
    q = clean_chain.mid()
    C = model.tag_in_camera(np.zeros(model.size), q[None])[0]
    assert np.allclose(C, L @ se3.inv(clean_chain.fk(q)) @ R, atol=1e-12)


def test_families_select_candidates(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    kinds = {model.params[i].kind for i in model.indices([Family.OFFSETS])}
    assert kinds == {"frame", "offset"}
    assert len(model.indices([Family.ORIGINS, Family.OFFSETS, Family.GAINS])) == model.size == 12 + 8 * clean_chain.n


@pytest.mark.parametrize("with_terms", [False, True])
@pytest.mark.parametrize("setup", list(Setup))
def test_twists_move_the_pose_as_the_parameters_do(clean_chain: Chain, setup: Setup, with_terms: bool) -> None:
    # The fit's Jacobian rests on this: changing parameter i by dx moves cMt by exp(dx·ε_i) on the
    # left, for every kind of parameter (both frames, origins, offsets, gains, joint terms) and both setups.
    rng = np.random.default_rng(3)
    terms = build_terms([Family.COMPLIANCE, Family.HARMONICS], clean_chain, CLEAN_ARM.read_text) if with_terms else ()
    L, R = se3.delta(rng.normal(size=6) * 0.3), se3.delta(rng.normal(size=6) * 0.3)
    model = CalibModel(clean_chain, setup, L, R, terms=terms)
    x = rng.normal(size=model.size) * 0.01
    Q = clean_chain.random(rng, 7)
    C, eps = model.twists(x, Q, list(range(model.size)))
    assert np.allclose(C, model.tag_in_camera(x, Q), atol=1e-12)
    for i in range(model.size):
        for dx in (1e-4, -1e-4):
            xp = x.copy()
            xp[i] += dx
            moved = model.tag_in_camera(xp, Q) @ se3.inv(C)
            seen = np.stack([np.concatenate([m[:3, 3], se3.log3(m[:3, :3])]) for m in moved])
            assert np.allclose(seen / dx, eps[:, :, i], atol=2e-3 * max(1.0, float(np.abs(eps[:, :, i]).max())))
