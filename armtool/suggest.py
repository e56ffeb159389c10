"""Did-you-mean for misspelled names (links, joints, plugins), and the known name a misspelling was
meant to be: the nearest within a few edits, for rules that tell a typo from another real name
(C104 controller types, K102 IK plugins)."""

from __future__ import annotations

from collections.abc import Callable, Iterable


def closest(name: str, candidates: Iterable[str]) -> str | None:
    import difflib  # on use: its import costs every `armtool lint` start ~1 ms, and most runs suggest nothing

    pool = sorted(set(candidates))
    matches = difflib.get_close_matches(name, pool, n=1, cutoff=0.6)
    if not matches:
        lowered = {c.lower(): c for c in pool}
        matches = difflib.get_close_matches(name.lower(), list(lowered), n=1, cutoff=0.6)
        matches = [lowered[m] for m in matches]
    return matches[0] if matches else None


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """' (did you mean 'x'?)' or '' when nothing is close."""
    match = closest(name, candidates)
    return f" (did you mean '{match}'?)" if match else ""


def levenshtein(a: str, b: str) -> int:
    """Insertions, deletions and substitutions (names are short: the plain dynamic programme is enough)."""
    previous = list(range(len(b) + 1))
    for i, ca in enumerate(a, 1):
        current = [i]
        for j, cb in enumerate(b, 1):
            current.append(min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (ca != cb)))
        previous = current
    return previous[-1]


def optimal_string_alignment(a: str, b: str) -> int:
    """Levenshtein's edits and a swap of neighbours, each substring edited once."""
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


def nearest_within(
    name: str,
    known: Iterable[str],
    max_edits: int,
    distance: Callable[[str, str], int],
    fold: Callable[[str], str] | None = None,
) -> str | None:
    """The first of `known` fewest edits (`distance`) from `name`, when that is at most
    `max_edits`; else None. With `fold` (str.lower) names are compared folded. A name whose
    length differs by more than `max_edits` is not measured: either distance is at least that."""
    wanted = fold(name) if fold is not None else name
    best: str | None = None
    fewest = max_edits + 1
    for candidate in known:
        other = fold(candidate) if fold is not None else candidate
        if abs(len(other) - len(wanted)) >= fewest:
            continue
        edits = distance(wanted, other)
        if edits < fewest:
            best, fewest = candidate, edits
    return best
