"""PathIK: with `lm`, its own first try gives lm's answer without building lm (no SciPy), and lm is
built and asked exactly where its first try would not have finished."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np

from armtool.ik.registry import make_solver
from armtool.model.chain import load_chain
from armtool.traj import cartesian as cart
from armtool.traj.path_ik import PathIK

from .helpers import CLEAN_URDF, START


def setup() -> tuple[object, np.ndarray, list[cart.Segment]]:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    q0 = np.array([float(v) for v in START.split(",")])
    T0 = chain.fk(q0)
    return chain, q0, [cart.circle_segment(T0, T0[:3, 3] + np.array([0, -0.1, 0]), np.array([1.0, 0, 0]), math.pi)]


def test_same_path_as_lm_without_building_lm() -> None:
    chain, q0, segs = setup()
    opts = cart.CartesianOptions(eef_step_m=0.005)
    ours = PathIK(chain, "lm")  # type: ignore[arg-type]
    a = cart.compute_cartesian(chain, ours, q0, segs, opts)  # type: ignore[arg-type]
    b = cart.compute_cartesian(chain, make_solver("lm", chain), q0, segs, opts)  # type: ignore[arg-type]
    assert a.fraction == b.fraction == 1.0 and a.q.shape == b.q.shape
    assert np.abs(a.q - b.q).max() < 1e-9
    assert ours.fallbacks == 0 and ours._solver is None  # lm itself was never built


def test_far_target_goes_to_lm() -> None:
    chain, q0, _ = setup()
    ik = PathIK(chain, "lm")  # type: ignore[arg-type]
    target = chain.fk(np.zeros(6))  # type: ignore[attr-defined]
    r = ik.solve(target, q0)
    assert ik.fallbacks == 1 and ik._solver is not None
    assert r.success and np.linalg.norm(chain.fk(r.q)[:3, 3] - target[:3, 3]) < 1e-5  # type: ignore[attr-defined]


def test_other_solvers_are_used_directly() -> None:
    chain, q0, _ = setup()
    ik = PathIK(chain, "dls")  # type: ignore[arg-type]
    r = ik.solve(chain.fk(q0), q0)  # type: ignore[attr-defined]
    assert r.success and type(ik.solver).__name__ == "DampedLeastSquares" and ik.fallbacks == 0


def test_cartesian_circle_imports_no_scipy(tmp_path: object) -> None:
    code = (
        "import sys\n"
        "from armtool.cli import main\n"
        f"sys.argv = ['armtool', 'traj', 'cartesian', {str(CLEAN_URDF)!r}, '--base', 'base_link', '--tip', 'tool0',"
        f" '--start', {START!r}, '--center-offset', '0,-0.1,0', '-o', {str(tmp_path)!r} + '/c.csv']\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('scipy', 'cv2', 'threadpoolctl')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "[]"


def test_a_solver_that_does_not_apply_fails_before_the_path() -> None:
    import pytest

    from armtool.errors import ArmtoolError
    from tests.ik.robots import erd

    panda = load_chain(erd("panda_description/urdf/panda.urdf"), "panda_link0", "panda_link8")
    with pytest.raises(ArmtoolError, match="closed form"):
        PathIK(panda, "analytic")
