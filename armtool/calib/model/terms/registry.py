"""The joint-term kinds, by the `--params` family that frees each (a new kind: one module, one line here)."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from armtool.calib.model.joint_term import JointTerm
from armtool.calib.model.params import Family
from armtool.model.chain import Chain


def _compliance(chain: Chain, urdf_xml: Callable[[], str]) -> JointTerm:
    from armtool.calib.model.terms.compliance import Compliance

    return Compliance(chain, urdf_xml())


def _harmonics(chain: Chain, urdf_xml: Callable[[], str]) -> JointTerm:
    from armtool.calib.model.terms.harmonics import Harmonics

    return Harmonics(chain)


TERMS: dict[Family, Callable[[Chain, Callable[[], str]], JointTerm]] = {
    Family.COMPLIANCE: _compliance,
    Family.HARMONICS: _harmonics,
}


def build_terms(families: Sequence[Family], chain: Chain, urdf_xml: Callable[[], str]) -> tuple[JointTerm, ...]:
    """The joint terms `--params` asks for, in the registry's order; `urdf_xml` gives the URDF's
    text, read only when a kind needs more than the chain (the inertials, for compliance)."""
    return tuple(build(chain, urdf_xml) for family, build in TERMS.items() if family in families)
