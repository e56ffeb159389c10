"""Apply safe fixes as text edits, so comments and formatting stay as the author wrote them."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable
from pathlib import Path

from armtool.lint.finding import Edit, Finding, FixSafety
from armtool.lint.registry import rule_class


def safe_edits(findings: Iterable[Finding]) -> list[tuple[Finding, Edit]]:
    out = []
    for f in findings:
        if f.edit is not None and rule_class(f.code).fix_safety is FixSafety.SAFE:
            out.append((f, f.edit))
    return out


def fixed_texts(pairs: list[tuple[Finding, Edit]]) -> dict[Path, tuple[str, str, list[Finding]]]:
    """path -> (old text, new text, findings fixed). Overlapping edits: the first one wins. A file
    that is not UTF-8 (an ISO-8859-1 declaration) gets no fix: its findings stay reported."""
    by_path: dict[Path, list[tuple[Finding, Edit]]] = defaultdict(list)
    for finding, edit in pairs:
        by_path[edit.path].append((finding, edit))
    out: dict[Path, tuple[str, str, list[Finding]]] = {}
    for path, items in by_path.items():
        try:
            old = path.read_bytes().decode("utf-8")
        except OSError as exc:
            from armtool.errors import ArmtoolError

            raise ArmtoolError(f"cannot read the file to fix: {exc.strerror or exc}", str(path)) from None
        except UnicodeDecodeError:
            continue  # edits are offsets into UTF-8 text: a file in another encoding is left as it is
        new = old
        applied: list[Finding] = []
        last_start = len(old) + 1
        seen: set[tuple[int, int]] = set()
        for finding, edit in sorted(items, key=lambda fe: fe[1].start, reverse=True):
            if (edit.start, edit.end) in seen:
                applied.append(finding)
                continue
            if edit.end > last_start:
                continue
            new = new[: edit.start] + edit.replacement + new[edit.end :]
            last_start = edit.start
            seen.add((edit.start, edit.end))
            applied.append(finding)
        if new != old:
            out[path] = (old, new, applied)
    return out


def unified_diff(path: Path, old: str, new: str, shown: str) -> str:
    import difflib

    return "".join(
        difflib.unified_diff(old.splitlines(keepends=True), new.splitlines(keepends=True), f"a/{shown}", f"b/{shown}")
    )


def write_atomic(path: Path, text: str) -> None:
    """--fix rewrites the user's file: whole or not at all, mode kept, symlinks followed (armtool.fileio)."""
    from armtool.fileio import write_atomic as write

    write(path, text)


__all__ = ["FixSafety", "fixed_texts", "safe_edits", "unified_diff", "write_atomic"]
