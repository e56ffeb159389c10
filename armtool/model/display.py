"""How a path is shown to users: relative to the working directory when below it, as they typed it.

Its own module so that lint (at start-up) and the xacro expander share it without importing each other.
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
