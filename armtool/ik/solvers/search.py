"""`search`: every IK solution of a 6R arm that has no closed form, by a 1-D search over one joint.

Kept apart from `analytic` on purpose: `analytic` is the closed form, and says plainly where an arm
has none; `search` is what to pick for such an arm when every solution matters (xArm6, Kinova
Gen3 lite: axes 4∩5 and 2∥3, or the same from the tip, without a spherical wrist). The method is
`closed_form/search.py` (IK-Geo's 1-D search: sample θ6, solve the rest by subproblems, refine the
roots of a scalar error, Newton-polish on the real chain); its output has the closed-form kernel's
layout, so the answers, the batch and `all_solutions` are `analytic`'s. It also runs on arms that do
have a closed form with that structure (a check on `analytic`, slower).
"""

from __future__ import annotations

from typing import Any, ClassVar

from armtool.ik.closed_form import search
from armtool.ik.solvers.analytic import Analytic
from armtool.model.chain import Chain


class Search(Analytic):
    name = "search"
    summary = "every solution by a 1-D search over one joint (IK-Geo's way) on 6R arms without a closed form whose axes 4∩5 and 2∥3 (or 2∩3 and 4∥5): xArm6, Kinova Gen3 lite"
    _entry: ClassVar[Any] = search
    _what: ClassVar[str] = "1-D search"

    def __init__(
        self, chain: Chain, timeout: float = 0.005, tolerance: float = 1e-5, seed: int | None = 0, **options: Any
    ) -> None:
        super(Analytic, self).__init__(chain, timeout=timeout, tolerance=tolerance, seed=seed, **options)
        self._model = search.pack(chain, self.tolerance)  # ArmtoolError when the chain lacks the structure
        self.geometry = None  # type: ignore[assignment]  # no closed-form family
        self._checked_here = False  # the search polishes and checks every answer on the chain itself
        self._set_limits()
        self._lanes = None
        self._lanes_ready = False
        self.method = search.title(bool(self._model[search.S_REVERSED]))
        self._load_kernel()

    @property
    def polished(self) -> bool:
        """The search polishes every root inside the kernel; nothing is polished afterwards."""
        return False
