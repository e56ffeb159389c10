"""The convention check names the reading that fits, with the dataset.yaml lines that select it."""

from __future__ import annotations

from pathlib import Path

import pytest

from armtool.calib.fit.convention_check import check_conventions
from armtool.calib.inputs.load import load_inputs
from armtool.model.chain import Chain
from tests.calib.measured_files import write_dataset
from tests.calib.synthetic import make_measured


def _check(path: Path):  # type: ignore[no-untyped-def]
    ds, chain, _camera = load_inputs(path)
    assert chain is not None and ds.measurement is not None and not ds.errors, ds.errors
    return check_conventions(chain, ds.setup, ds.measurement, ds.measured_rows, ds.samples)


@pytest.mark.parametrize(
    ("wrong", "fix"),
    [
        # columns listed as q0..q3 holding w x y z, declared x y z w
        (
            {"rotation_columns": ["qw", "qx", "qy", "qz"], "quaternion_order": "xyzw"},
            ["observations.quaternion_order: wxyz"],
        ),
        ({"position_units": "mm"}, ["observations.position_units: m"]),  # metres declared as millimetres
        ({"pose": "target_in_sensor"}, ["observations.pose: sensor_in_target"]),
    ],
)
def test_a_wrong_declaration_is_found(tmp_path: Path, clean_chain: Chain, wrong: dict, fix: list[str]) -> None:  # type: ignore[type-arg]
    # (millimetres declared as metres are caught row by row: positions beyond 100 m)
    m = make_measured(clean_chain, "pose", n=25, seed=21)
    found = _check(write_dataset(tmp_path / "ds", m, rotation="quaternion", units="m", manifest=wrong))
    assert found.better is not None
    assert found.better.changes == fix
    # the reading named is the file's true one: it fits as the correctly declared file does (the
    # nominal robot against the injected errors: a few mm), the declared one is off by far more
    right = _check(write_dataset(tmp_path / "right", m, rotation="quaternion", units="m"))
    assert found.better.position_mm == pytest.approx(right.declared.position_mm, rel=1e-9)
    assert found.better.rotation_deg == pytest.approx(right.declared.rotation_deg, rel=1e-9)
    assert found.better.position_mm < 5.0 and found.declared.position_mm > 300.0
    assert found.fix().startswith("in dataset.yaml, set " + "; ".join(fix))


def test_the_right_declaration_is_left_alone(tmp_path: Path, clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "pose", n=25, seed=22)
    found = _check(write_dataset(tmp_path / "ds", m, rotation="matrix", units="m"))
    assert found.better is None and found.fix() == ""
    assert found.tried == 16  # 2 frames × 2 units × 2 matrix orders × 2 setups
    assert "the declared conventions fit best" in found.message()
