"""How a path is shown to users: relative to the working directory when below it, as they typed it;
and the notes that name a place in another file in a message ("... (at arm.xacro:7)").

Its own module so that lint (at start-up) and the xacro expander share it without importing each other.
Each note is written here only: lint's shared-defect merge (armtool.lint.shared_defects) finds
it in messages to take it out again.
"""

from __future__ import annotations

import os
from pathlib import Path


def display_path(path: Path) -> str:
    try:
        rel = os.path.relpath(path)
    except ValueError:
        return str(path)
    return str(path) if rel.startswith("..") else rel


def macro_body_note(path: str, line: int) -> str:
    """Where an element a macro made was written (`path` as display_path shows it)."""
    return f"from the macro body at {path}:{line}"


def included_file_note(path: str, line: int) -> str:
    """Where in an included file xacro failed (`path` as display_path shows it)."""
    return f"at {path}:{line}"


def note_suffix(note: str) -> str:
    """A note as it follows a message: ' (note)'."""
    return f" ({note})"
