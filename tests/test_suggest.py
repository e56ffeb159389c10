"""nearest_within: the known name a misspelling was meant to be, as C104 and K102 find it. Checked
against the rules' own code before it was shared (copied here), on names near the known ones."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from armtool.lint.rules.c104_unknown_controller_type import TYPO
from armtool.lint.rules.k102_unknown_solver_plugin import KNOWN_PLUGINS, MAX_TYPO_EDITS, near_miss
from armtool.moveit.controllers import ROS1_TYPES, ROS2_TYPES
from armtool.suggest import levenshtein, nearest_within, optimal_string_alignment


def _c104_edits(a: str, b: str) -> int:  # C104's `edits` before nearest_within (its cap included)
    if abs(len(a) - len(b)) > TYPO:
        return TYPO + 1
    previous2: list[int] = []
    previous = list(range(len(b) + 1))
    for i, ca in enumerate(a, 1):
        current = [i]
        for j, cb in enumerate(b, 1):
            cost = 0 if ca == cb else 1
            best = min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost)
            if i > 1 and j > 1 and ca == b[j - 2] and a[i - 2] == cb:
                best = min(best, previous2[j - 2] + 1)
            current.append(best)
        previous2, previous = previous, current
    return previous[-1]


def _c104_before(text: str, known: tuple[str, ...]) -> str | None:
    nearest = min(known, key=lambda k: _c104_edits(text, k))
    return nearest if _c104_edits(text, nearest) <= TYPO else None


def _k102_before(value: str) -> str | None:  # the first half of near_miss before nearest_within
    best = min(KNOWN_PLUGINS, key=lambda k: levenshtein(value.lower(), k.lower()))
    return best if levenshtein(value.lower(), best.lower()) <= MAX_TYPO_EDITS else None


@st.composite
def misspelt(draw: st.DrawFn, names: tuple[str, ...]) -> str:
    """A known name with a few random edits (deletions, insertions, substitutions, swaps, case)."""
    text = list(draw(st.sampled_from(names)))
    for _ in range(draw(st.integers(0, 5))):
        if not text:
            break
        i = draw(st.integers(0, len(text) - 1))
        op = draw(st.sampled_from(["del", "ins", "sub", "swap", "case"]))
        char = draw(st.sampled_from("aeiorstlnJCP_/:x"))
        if op == "del":
            del text[i]
        elif op == "ins":
            text.insert(i, char)
        elif op == "sub":
            text[i] = char
        elif op == "swap" and i + 1 < len(text):
            text[i], text[i + 1] = text[i + 1], text[i]
        elif op == "case":
            text[i] = text[i].swapcase()
    return "".join(text)


ROS2 = tuple(sorted(ROS2_TYPES))
ROS1 = tuple(sorted(ROS1_TYPES))


@settings(max_examples=300, deadline=None)
@given(misspelt(ROS2 + ROS1))
def test_c104_finds_the_type_it_found_before(text: str) -> None:
    for known in (ROS2, ROS1):
        assert nearest_within(text, known, TYPO, optimal_string_alignment) == _c104_before(text, known)


@settings(max_examples=300, deadline=None)
@given(misspelt(KNOWN_PLUGINS))
def test_k102_finds_the_plugin_it_found_before(value: str) -> None:
    assert nearest_within(value, KNOWN_PLUGINS, MAX_TYPO_EDITS, levenshtein, fold=str.lower) == _k102_before(value)


def test_examples() -> None:
    assert near_miss("kdl_kinematics_plugin/KDLKinematicPlugin") == "kdl_kinematics_plugin/KDLKinematicsPlugin"
    assert near_miss("KDL_KINEMATICS_PLUGIN/KDLKINEMATICSPLUGIN") == "kdl_kinematics_plugin/KDLKinematicsPlugin"
    typo = "joint_trajectory_controller/JointTrajectroyController"  # a swap: one edit for C104, two for Levenshtein
    assert nearest_within(typo, ROS2, TYPO, optimal_string_alignment) == (
        "joint_trajectory_controller/JointTrajectoryController"
    )
    assert (
        nearest_within("position_controllers/PilzJointTrajectoryController", ROS1, TYPO, optimal_string_alignment)
        is None
    )
    assert optimal_string_alignment("ab", "ba") == 1 and levenshtein("ab", "ba") == 2
    assert nearest_within("abc", ["abd", "abe"], 1, levenshtein) == "abd"  # the first of the nearest
    assert nearest_within("abc", [], 1, levenshtein) is None
