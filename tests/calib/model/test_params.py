"""The parameter layout: one owner of the offsets, agreeing with the parameter names, views that write through."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import Family, ParamKind, ParamLayout, parse_families
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain
from tests.calib.conftest import CLEAN_ARM, nominal_model


def model_with_terms(chain: Chain) -> CalibModel:
    from armtool.calib.model.terms.registry import build_terms

    terms = build_terms([Family.COMPLIANCE, Family.HARMONICS], chain, CLEAN_ARM.read_text)
    return CalibModel(chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4), terms=terms)


def test_layout_offsets_name_the_parameters_they_point_at(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    layout = model.layout
    assert layout.size == model.size == len(model.params)
    assert {model.params[i].kind for i in layout.frames} == {ParamKind.FRAME}
    for j, joint in enumerate(clean_chain.joints):
        names = [model.params[i].name for i in layout.origin(j)]
        assert names == [f"{joint.name}.origin.{c}" for c in ("tx", "ty", "tz", "rx", "ry", "rz")]
        assert [model.params[i].name for i in layout.origin_rotation(j)] == names[3:]
        assert model.params[layout.offset(j)].name == f"{joint.name}.offset"
        assert model.params[layout.gain(j)].kind is ParamKind.GAIN


def test_split_gives_views_by_meaning_that_write_through(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    x = np.zeros(model.size)
    parts = model.split(x)
    assert parts.left.shape == parts.right.shape == (6,)
    assert parts.origin.shape == (clean_chain.n, 6) and parts.offset.shape == parts.gain_error.shape == (clean_chain.n,)
    parts.offset[2] = 0.25
    parts.origin[1, 4] = -0.5
    parts.right[0] = 1.0
    assert x[model.layout.offset(2)] == 0.25 and x[model.layout.origin(1)[4]] == -0.5 and x[6] == 1.0
    assert np.count_nonzero(x) == 3


def test_split_refuses_a_vector_of_another_layout() -> None:
    with pytest.raises(ValueError, match="layout of size 20"):
        ParamLayout(1).split(np.zeros(21))


def test_each_family_frees_its_own_kind(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    for family in (Family.ORIGINS, Family.OFFSETS, Family.GAINS):
        chosen = {model.params[i].kind for i in model.indices([family])}
        assert chosen == {ParamKind.FRAME, family.kind}
    with_terms = model_with_terms(clean_chain)
    for family in (Family.COMPLIANCE, Family.HARMONICS):
        chosen = {with_terms.params[i].kind for i in with_terms.indices([family])}
        assert chosen == {ParamKind.FRAME, family.kind}


def test_joint_terms_follow_the_joints_and_have_their_own_offsets(clean_chain: Chain) -> None:
    model = model_with_terms(clean_chain)
    n = clean_chain.n
    assert model.size == 12 + 8 * n + n * (1 + 4)
    layout = model.layout
    for j, name in enumerate(clean_chain.joint_names):
        assert [model.params[i].name for i in layout.term(0, j)] == [f"{name}.sag"]
        assert [model.params[i].name for i in layout.term(1, j)] == [
            f"{name}.{c}" for c in ("sin1", "cos1", "sin2", "cos2")
        ]
    x = np.arange(model.size, dtype=float)
    parts = model.split(x)
    assert parts.terms[0][2, 0] == layout.term(0, 2)[0] and parts.terms[1][1, 3] == layout.term(1, 1)[3]


def test_parse_families_keeps_order_once_and_names_the_choices() -> None:
    assert parse_families(" offsets,origins,offsets ") == (Family.OFFSETS, Family.ORIGINS)
    with pytest.raises(ArmtoolError) as info:
        parse_families("origins,gain")
    assert "unknown parameter family 'gain'" in info.value.what and info.value.hint == (
        "choose from: " + ", ".join(f.value for f in Family) + ", none"
    )
    with pytest.raises(ArmtoolError, match="--params is empty"):
        parse_families(" , ")


def test_params_none_is_hand_eye_only_and_alone() -> None:
    assert parse_families("none") == ()
    with pytest.raises(ArmtoolError, match="cannot be combined"):
        parse_families("none,offsets")


def test_the_choices_module_stays_free_of_numpy() -> None:
    # The command modules import it at start-up to build their options (tests/test_startup_imports.py).
    code = "import sys, armtool.calib.choices; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
