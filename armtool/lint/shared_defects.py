"""One defect, one finding: a defect inside a file that several linted files include (a macro
body, a broken include) is reported once, where it is written, naming the files that include it.

A finding on an element a macro made points at the call in the file you linted, and says where
the macro body is (`related` ends with that place); an X001 points at the include that leads to
xacro's error, with the place inside the included file last in its trail. When two or more
linted files give the same finding (same code and message) for the same place in an included
file, that place is the defect: one finding there replaces theirs. A finding only one linted
file gives stays at its call site, as before.
"""

from __future__ import annotations

from collections import defaultdict

from armtool.lint.finding import Finding
from armtool.model.display import included_file_note, macro_body_note, note_suffix

MAX_NAMED = 5  # files named in the message; the rest are counted


def _anchor(finding: Finding) -> tuple[str, int] | None:
    """The place in another file that a finding stands for (a macro body, an included file)."""
    if not finding.related:
        return None
    place = finding.related[-1]
    return place if place[0] != finding.path else None


def _without_place(message: str, anchor: tuple[str, int]) -> str:
    """The message without the note that names the anchor (it becomes the finding's place)."""
    path, line = anchor
    for note in (macro_body_note(path, line), included_file_note(path, line)):
        written = note_suffix(note)
        if written in message:
            return message.replace(written, "")
    return message


def merge_shared_defects(findings: list[Finding]) -> list[Finding]:
    """`findings` with each defect that several linted files share reported once, at its place."""
    groups: dict[tuple[str, str, tuple[str, int]], list[Finding]] = defaultdict(list)
    for finding in findings:
        anchor = _anchor(finding)
        if anchor is not None:
            groups[(finding.code, finding.message, anchor)].append(finding)
    out: list[Finding] = []
    merged: set[int] = set()
    own = {(f.path, f.line, f.code, f.message): f for f in findings if _anchor(f) is None}
    for (code, message, anchor), members in groups.items():
        files = list(dict.fromkeys(f.path for f in members))
        if len(files) < 2:
            continue
        merged.update(id(f) for f in members)
        base = _without_place(message, anchor)
        itself = own.get((anchor[0], anchor[1], code, base))  # the included file, linted on its own too
        if itself is not None:
            merged.add(id(itself))
        named = ", ".join(files[:MAX_NAMED]) + (f" and {len(files) - MAX_NAMED} more" if len(files) > MAX_NAMED else "")
        first = members[0]
        related = tuple(dict.fromkeys(place for f in members for place in ((f.path, f.line), *f.related)))
        out.append(
            first._replace(
                path=anchor[0],
                line=anchor[1],
                column=itself.column if itself is not None else 1,
                message=f"{base} (in every file that includes it: {named})",
                related=tuple(p for p in related if p != anchor),
            )
        )
    return [f for f in findings if id(f) not in merged] + out
