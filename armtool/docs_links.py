"""Where the manual lives: every command's help ends with a link to its page, and SARIF's rule
links point into it. The pages are docs/*.md of the repository (GitHub renders them; `make docs`
builds them into a site)."""

from __future__ import annotations

DOCS_URL = "https://github.com/armtool/armtool/blob/main/docs/"

# command -> its page in docs/
COMMAND_PAGES: dict[str, str] = {
    "lint": "lint.md",
    "lint-urdf": "lint.md",
    "rules": "rules.md",
    "expand": "tree-expand.md",
    "tree": "tree-expand.md",
    "ik-bench": "ik-bench.md",
    "calibrate": "calibrate.md",
    "limits": "limits.md",
    "servo-sim": "limits.md",
    "servo-lut": "servo-lut.md",
    "traj": "traj.md",
}


def manual_link(command: str | None = None) -> str:
    """The line a help text ends with: the URL of the command's page (the manual's home for None)."""
    return "Manual: " + DOCS_URL + (COMMAND_PAGES.get(command, "index.md") if command else "index.md")
