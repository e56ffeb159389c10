"""The IK of `traj cartesian`: `lm` itself, with its table of poses built only when a point needs it."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik.registry import make_solver
from armtool.model.chain import load_chain
from armtool.traj import cartesian as cart
from armtool.traj.plan import PathSpec, plan_cartesian

from .helpers import CLEAN_URDF, START


def setup() -> tuple[object, np.ndarray, list[cart.Segment]]:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    q0 = np.array([float(v) for v in START.split(",")])
    T0 = chain.fk(q0)
    return chain, q0, [cart.circle_segment(T0, T0[:3, 3] + np.array([0, -0.1, 0]), np.array([1.0, 0, 0]), math.pi)]


def test_a_path_builds_no_table_and_a_far_target_builds_it() -> None:
    chain, q0, segs = setup()
    lazy = make_solver("lm", chain, lazy_table=True)  # type: ignore[arg-type]
    eager = make_solver("lm", chain)  # type: ignore[arg-type]
    opts = cart.CartesianOptions(eef_step_m=0.005)
    a = cart.compute_cartesian(chain, lazy, q0, segs, opts)  # type: ignore[arg-type]
    b = cart.compute_cartesian(chain, eager, q0, segs, opts)  # type: ignore[arg-type]
    assert a.fraction == b.fraction == 1.0 and np.array_equal(a.q, b.q)  # the same solver either way
    assert lazy._table is None  # type: ignore[attr-defined]  # every point solved from its seed
    target = chain.fk(np.zeros(6))  # type: ignore[attr-defined]
    r = lazy.solve(target, q0)
    assert r.success and lazy._table is not None  # type: ignore[attr-defined]


def test_cartesian_circle_builds_no_table(tmp_path: object) -> None:
    # lm's table (32768 poses, SciPy's k-d tree) costs ~0.3 s of CPU and a path never needs it; nor
    # does it need SciPy's optimizers or OpenCV. (Numba, which runs lm's loop, loads SciPy's BLAS.)
    code = (
        "import sys\n"
        "from armtool.cli import main\n"
        f"sys.argv = ['armtool', 'traj', 'cartesian', {str(CLEAN_URDF)!r}, '--base', 'base_link', '--tip', 'tool0',"
        f" '--start', {START!r}, '--center-offset', '0,-0.1,0', '-o', {str(tmp_path)!r} + '/c.csv']\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
        "heavy = ('scipy.spatial', 'scipy.optimize', 'cv2', 'threadpoolctl')\n"
        "print(sorted(m for m in sys.modules if m.startswith(heavy)))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "[]"


def test_a_solver_that_does_not_apply_fails_before_the_path() -> None:
    from tests.ik.robots import erd

    panda = erd("panda_description/urdf/panda.urdf")
    spec = PathSpec(line="0,0,0.01", relative=True)
    with pytest.raises(ArmtoolError, match="closed form"):
        plan_cartesian(panda, "panda_link0", "panda_link8", None, spec, cart.CartesianOptions(), "analytic")
