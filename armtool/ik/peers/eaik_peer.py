"""Peer `eaik`: EAIK's C++ subproblem decomposition (pip `eaik`, BSD-3), every solution in closed form.

Configuration, as a user sets it up: `eaik.IK_URDF.UrdfRobot(path)` reads the chain's URDF (the
chain's path only, `path_urdf`: EAIK's reader, urchin, takes every actuated joint of the file, a
gripper's too), `hasKnownDecomposition()` says whether it can solve the arm, `getKinematicFamily()`
which decomposition it found (the row's method). A solve is `IK(T)`, a batch `IK_batched(poses,
num_worker_threads=1)` (one thread, like every other row), each returning solutions `Q` with
`is_LS` (least-squares approximations, kept but never claimed).

- Frames: EAIK's tool frame is the last joint's frame turned back to the base's orientation
  (its R6T is the identity, its last offset zero), not the URDF's tip. Its FK and ours differ by a
  constant tool transform C (chain.fk(q) = EAIK.fwdKin(q)·C, `tool_transform`), proven on random
  configurations at construction (`check_fk`); prepare turns a target T into T·C⁻¹ (untimed).
- Joint limits: EAIK ignores them. Its solutions are moved by whole turns into the limits where
  possible and ordered nearest the seed first (`armtool.ik.solutions.closed_form_answer`), as
  `analytic` places its own; the row is solved when any of them passes armtool's check.
- Locked joints (`ik-bench --lock`, `Chain.locked`): EAIK gets the whole chain's URDF and its own
  `fixed_axes=[(index, value)]`, not a URDF with the joints made fixed; its FK then takes and its
  solutions give every joint, the locked ones at their values, which `answer` drops.
- Arms it cannot take get a row with the reason (EAIK's own words where it has them): prismatic
  joints, more than 6 joints (EAIK solves 1-6R chains: a 7-DOF arm needs a joint locked, `--lock`),
  no known decomposition (xArm6, Kinova Gen3 lite).
- The timed call is `IK(T)` itself (EAIK's Python method around its C++ `calculate_IK`, what a user
  calls); reading `Q` and `is_LS` out of its result is `answer`, untimed.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.peers import check_closed_form_chain, check_fk, path_urdf, tool_transform
from armtool.ik.solutions import closed_form_answer
from armtool.ik.solver import Answer, Array, Solver
from armtool.model.chain import Chain

MAX_JOINTS = 6  # EAIK: "Currently, only 1-6R robots are solvable with EAIK"
BATCH_THREADS = 1  # IK_batched's worker threads: one, as every row of the benchmark runs on one


class Eaik(Solver):
    name = "eaik"
    summary = "EAIK (C++, pip eaik): subproblem decomposition from the URDF, every solution in closed form"
    returns_all_solutions = True
    takes_locks = True  # locked joints as EAIK's fixed_axes on the whole chain's URDF (make_peer)

    def __init__(self, chain: Chain, root: etree._Element, *, timeout: float, tolerance: float) -> None:
        Solver.__init__(self, chain, timeout=timeout, tolerance=tolerance)
        check_closed_form_chain(
            "EAIK",
            chain,
            max_joints=MAX_JOINTS,
            beyond="it solves 1-6R chains: lock one joint of a 7-DOF arm (--lock JOINT=VALUE, EAIK's fixed_axes)",
        )
        fixed = [(index, value) for index, _, value in chain.locks]
        self._moving = [i for i in range(chain.n + len(fixed)) if i not in {index for index, _ in fixed}]
        from eaik.IK_URDF import UrdfRobot

        with tempfile.TemporaryDirectory(prefix="armtool-eaik-") as tmp:
            path = Path(tmp) / "chain.urdf"
            path.write_bytes(etree.tostring(path_urdf(root, chain), xml_declaration=True, encoding="utf-8"))
            try:
                robot: Any = UrdfRobot(str(path), fixed_axes=fixed)
            except RuntimeError as exc:  # EAIK refuses the chain, in its own words
                raise ArmtoolError(f"EAIK cannot take this chain: {exc}") from None
        self.method = str(robot.getKinematicFamily())
        if not robot.hasKnownDecomposition():
            raise ArmtoolError(
                f"EAIK knows no subproblem decomposition for this arm (EAIK: {self.method}): "
                "no spherical wrist, three parallel axes or other family it solves in closed form"
            )

        def fk(q: Array) -> Array:  # EAIK's FK takes every joint of its chain, the locked ones too
            return robot.fwdKin(chain.expand(np.asarray(q, dtype=float)))  # type: ignore[no-any-return]

        self._tool = tool_transform(chain, fk)
        self._to_eaik = np.linalg.inv(self._tool)
        check_fk(self.name, chain, lambda q: fk(q) @ self._tool)
        self._ik = robot.IK
        self._ik_batched = robot.IK_batched

    def prepare(self, target: Array, seed: Array) -> tuple[Array, Array]:
        """EAIK's pose: the target in EAIK's tool frame (T·C⁻¹), a contiguous 4x4 of doubles."""
        pose = np.ascontiguousarray(np.asarray(target, dtype=float) @ self._to_eaik)
        return pose, np.asarray(seed, dtype=float)

    def call(self, prepared: tuple[Array, Array]) -> tuple[Any, Array]:
        return self._ik(prepared[0]), prepared[1]

    def answer(self, raw: tuple[Any, Array]) -> Answer:
        solution, seed = raw
        Q = np.asarray(solution.Q, dtype=float).reshape(-1, len(self._moving) + len(self.chain.locks))
        return closed_form_answer(self.chain, self.name, Q[:, self._moving], solution.is_LS, seed)

    def prepare_batch(self, targets: Array, seeds: Array) -> tuple[list[Array], Array]:
        targets, seeds = self._batch_arrays(targets, seeds)
        return [self.prepare(t, s)[0] for t, s in zip(targets, seeds)], seeds

    def call_batch(self, prepared: tuple[list[Array], Array]) -> tuple[Any, Array]:
        return self._ik_batched(prepared[0], BATCH_THREADS), prepared[1]

    def answer_batch(self, raw: tuple[Any, Array]) -> list[Answer]:
        solutions, seeds = raw
        return [self.answer((s, seed)) for s, seed in zip(solutions, seeds)]
