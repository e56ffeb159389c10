"""stdout carries data only; messages, progress and hints go to stderr."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rich.console import Console
    from rich.progress import Progress

_stderr: Console | None = None


def stderr() -> Console:
    """The rich console for humans (stderr), created on first use to keep start-up fast."""
    global _stderr
    if _stderr is None:
        from rich.console import Console

        _stderr = Console(stderr=True, highlight=False, soft_wrap=True)
    return _stderr


def say(text: str, *, label: str = "", style: str = "") -> None:
    """Print a message on stderr as plain text (file names, file contents, hints with `[...]` stay as
    they are; rich markup would eat `armtool[peers]`), after an optional styled label such as "warning:"."""
    from rich.text import Text

    line = Text()
    if label:
        line.append(label, style=style or None)
        line.append(" ")
    line.append(text)
    stderr().print(line)


def progress_bar(label_width: int = 18) -> Progress:
    """The progress bar every long subcommand shows on stderr: label, bar, done/total, time left.
    Only on a terminal: into a log or a pipe, a live display leaves a stray empty line (before an
    error message, too)."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    console = stderr()
    return Progress(
        TextColumn(f"{{task.description:<{label_width}}}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeRemainingColumn(),
        console=console,
        transient=True,
        disable=not console.is_terminal,
    )


def write_stdout(text: str) -> None:
    sys.stdout.write(text)
    if text and not text.endswith("\n"):
        sys.stdout.write("\n")
    sys.stdout.flush()
