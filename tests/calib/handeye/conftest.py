"""`rendered`: hand-eye datasets with known truth (tests/calib/handeye_data.py), each spec rendered
once per test session."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from armtool.calib.handeye.simulate import HandEyeSimulation, Rendered, render, write_dataset
from tests.calib.handeye_data import DEFAULTS, Make


@pytest.fixture(autouse=True)
def _one_blas_thread() -> Iterator[None]:
    """As `run_handeye` does: the fits' matrices are small, and BLAS threads only contend."""
    import scipy.optimize  # noqa: F401  (SciPy's BLAS loaded before it is limited)

    from armtool.calib.fit.calibration import one_blas_thread

    with one_blas_thread():
        yield


@pytest.fixture(scope="session")
def rendered(tmp_path_factory: pytest.TempPathFactory) -> Make:
    """`rendered(**spec)`: (dataset directory, what was rendered) of HandEyeSimulation(**DEFAULTS, **spec)."""
    cache: dict[str, tuple[Path, Rendered]] = {}

    def make(**spec: Any) -> tuple[Path, Rendered]:
        key = repr(sorted(spec.items()))
        if key not in cache:
            simulation = HandEyeSimulation(**{**DEFAULTS, **spec})
            out = tmp_path_factory.mktemp("handeye") / "dataset"
            result = render(simulation)
            write_dataset(out, simulation, result)
            cache[key] = (out, result)
        return cache[key]

    return make
