"""Which rows an `ik-bench` run has: the built-in solvers and the peers that can take the chain, a
row with the reason for each that cannot, and the peers that are not installed.

A solver or peer that cannot take the chain (no closed form, too many joints, a position-only
group) is not an error: its row says why (`NotApplicable`), and the others run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.bench import Entry, NotApplicable
from armtool.ik.peers import make_peer
from armtool.ik.registry import solver_class
from armtool.ik.solver import Solver
from armtool.model.chain import Chain

POSITION_ONLY_SOLVER = "it solves full poses of the real chain only; this group is position-only (position_only_ik)"
POSITION_ONLY_PEER = "peers solve full poses only; this group is position-only (position_only_ik)"


def _reason(exc: ArmtoolError) -> str:
    return exc.what + (f" (hint: {exc.hint})" if exc.hint else "")


@dataclass
class Lineup:
    chain: Chain  # the chain the solvers solve (position-only: with a free virtual wrist at the tip)
    solvers: list[Solver] = field(default_factory=list)  # built-in solvers, then peers, in the order asked
    not_applicable: list[NotApplicable] = field(default_factory=list)
    not_installed: list[tuple[str, str]] = field(default_factory=list)  # (peer, how to install it)

    def entries(self, batch: bool) -> list[Entry]:
        """One row per solver, and with `batch` a second for each that solves many targets its own way."""
        rows = [Entry(s) for s in self.solvers]
        return rows + ([Entry(s, batch=True) for s in self.solvers if s.has_batch()] if batch else [])


def build_lineup(
    names: Sequence[str],
    peers: Sequence[str],
    chain: Chain,
    root: etree._Element,
    *,
    timeout: float,
    tolerance: float,
    seed: int,
    position_only: bool,
) -> Lineup:
    """Build every solver (on the position-only chain for a position-only group) and every peer (on
    the real chain); unknown names raise (a usage error)."""
    solve_chain = chain.with_free_orientation() if position_only else chain
    lineup = Lineup(solve_chain)
    for name in names:
        cls = solver_class(name)
        if position_only and not cls.position_only_capable:
            lineup.not_applicable.append(NotApplicable(name, POSITION_ONLY_SOLVER))
            continue
        try:
            lineup.solvers.append(cls(solve_chain, timeout=timeout, tolerance=tolerance, seed=seed))
        except ArmtoolError as exc:  # e.g. no closed form for this chain
            lineup.not_applicable.append(NotApplicable(name, _reason(exc)))
    for name in peers:
        if position_only:
            lineup.not_applicable.append(NotApplicable(name, POSITION_ONLY_PEER))
            continue
        try:
            peer = make_peer(name, chain, root, timeout=timeout, tolerance=tolerance)
        except ArmtoolError as exc:  # e.g. EAIK: no decomposition, or 7 joints
            lineup.not_applicable.append(NotApplicable(name, _reason(exc)))
            continue
        if isinstance(peer, str):
            lineup.not_installed.append((name, peer))
        else:
            lineup.solvers.append(peer)
    return lineup


def names_option(
    flag: str, text: str | None, known: list[str], everything: str = "", what: str = "solver"
) -> list[str]:
    """ik-bench's --solvers/--peers: a comma-separated list of names (None: every known one). An empty list (`--solvers ,`) is an
    error: it would run an empty benchmark and exit 0. Unknown names are reported where they are built."""
    if text is None:
        return list(known)
    if everything and text.strip() == everything:
        return list(known)
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise ArmtoolError(
            f"{flag} {text!r} names no {what}",
            hint=f"choose from: {', '.join(known)}" + (f", or {everything}" if everything else ""),
        )
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ArmtoolError(f"{flag} names {', '.join(repeated)} twice", hint=f"list each {what} once")
    return names
