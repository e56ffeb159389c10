"""benchmarks/traj_bench.py judges every timing method by its own exact trajectory, never through
armtool's resampling and interpolation of it."""

from __future__ import annotations

from typing import Any

import numpy as np

from armtool.traj.limits import JointLimits
from tests.benchmarks import load_script


def limits(v: float, a: float) -> JointLimits:
    one = np.array([1.0])
    return JointLimits(("j",), -10 * one, 10 * one, v * one, a * one, np.nan * one, (False,), ("test",))


def bang_bang(a_max: float, duration: float, spike: tuple[float, float, float] | None = None) -> Any:
    """Rest to rest on one joint at exactly ±a_max (switching mid-way), the way a time-optimal
    timer's constant-acceleration pieces are; `spike` = (start, end, acceleration) overrides it."""

    def evaluate(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        half = duration / 2
        acc = np.where(t < half, a_max, -a_max)
        if spike is not None:
            acc = np.where((t >= spike[0]) & (t < spike[1]), spike[2], acc)
        vel = np.where(t < half, a_max * t, a_max * (duration - t))
        pos = np.where(t < half, 0.5 * a_max * t**2, a_max * half**2 - 0.5 * a_max * (duration - t) ** 2)
        return pos[:, None], vel[:, None], acc[:, None]

    return evaluate


def test_a_peer_at_its_limit_is_not_judged_over_it() -> None:
    # Sampled at 100 Hz and re-interpolated with a cubic Hermite (what armtool's checker assumes of its
    # own output), an exact bang-bang profile appears up to ~1.5x over its acceleration limit at the
    # switch; by its own evaluation it is exactly at the limit.
    script = load_script("traj_bench")
    lim = limits(v=10.0, a=2.0)
    v, a = script.worst_exact(bang_bang(2.0, 1.0), 1.0, lim)
    assert a <= 1.0 + 1e-12 and v <= 0.11


def test_a_peer_over_its_limit_between_samples_is_caught() -> None:
    # 1.3x the limit for 2 ms, between two 100 Hz samples: the exact grid sees it.
    script = load_script("traj_bench")
    lim = limits(v=10.0, a=2.0)
    _, a = script.worst_exact(bang_bang(2.0, 1.0, spike=(0.2031, 0.2051, 2.6)), 1.0, lim)
    assert abs(a - 1.3) < 1e-12


def test_toppra_is_judged_by_its_own_trajectory() -> None:
    # toppra_time hands back toppra's own evaluation (jt(t), jt(t, 1), jt(t, 2)), not samples of it.
    import pytest

    pytest.importorskip("toppra")
    from armtool.traj.path import joint_path

    script = load_script("traj_bench")
    lim = limits(v=1.0, a=2.0)
    path = joint_path(np.array([[0.0], [0.5], [0.2], [1.0]]))
    for parametrizer in script.TOPPRA_PARAMETRIZERS:
        duration, evaluate = script.toppra_time(path, lim, parametrizer)
        t = np.linspace(0.0, duration, 7)
        q, qd, qdd = evaluate(t)
        assert q.shape == qd.shape == qdd.shape == (7, 1)
        assert abs(q[0, 0]) < 1e-9 and abs(q[-1, 0] - 1.0) < 1e-6
