"""Keep the documented armtool output true: run every marked example of README.md and docs/*.md
and write its real output into the page (default), or fail when a page has drifted (--check).

A kept example is a marker comment and the fenced block after it:

    <!-- run: armtool lint fixtures/robots/broken_arm -->
    ```console
    $ armtool lint fixtures/robots/broken_arm
    (its output)
    ```

The command runs from the repository root in a shell (pipes and `;` allowed), with the `armtool`
beside this Python first on PATH, a 100-column terminal, no colours and unbuffered output, so
stdout and stderr interleave as a user sees them; the checkout's own path is shown relative (as
the command named it). Write outputs under build/ (ignored by git). The marker may carry options before the colon:
`exit=N` (the exit code the example expects; default 0: any other code means the example no longer
runs), and `varies` (its output holds timings or other numbers that change from run to run: --check
then compares it with every number masked and runs of spaces collapsed).

    python tools/docs_examples.py            # rewrite the blocks
    python tools/docs_examples.py --check    # exit 1 and show what drifted
"""

from __future__ import annotations

import argparse
import difflib
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGES = ["README.md", "docs/*.md"]
MARKER = re.compile(
    r"^<!-- run(?P<options>[^:]*): (?P<command>.+?) -->\n```(?P<lang>\w*)\n(?P<body>.*?)```$", re.M | re.S
)
TIMEOUT_S = 300


@dataclass(frozen=True)
class Example:
    page: Path
    start: int  # offset of the block's body in the page
    end: int
    command: str
    exit_code: int
    varies: bool
    body: str


def pages(root: Path = ROOT) -> list[Path]:
    out: list[Path] = []
    for pattern in PAGES:
        out += sorted(root.glob(pattern))
    return out


def examples(page: Path) -> list[Example]:
    text = page.read_text(encoding="utf-8")
    found = []
    for m in MARKER.finditer(text):
        options = m.group("options").split()
        exit_code, varies = 0, False
        for option in options:
            if option == "varies":
                varies = True
            elif option.startswith("exit="):
                exit_code = int(option.split("=", 1)[1])
            else:
                raise SystemExit(f"{page}: unknown option {option!r} in a run marker (exit=N, varies)")
        found.append(
            Example(page, m.start("body"), m.end("body"), m.group("command"), exit_code, varies, m.group("body"))
        )
    return found


def run(example: Example) -> tuple[str, int]:
    """The block's new body: `$ command` and the output, and the exit code."""
    env = {
        **os.environ,
        "PATH": str(Path(sys.executable).parent) + os.pathsep + os.environ.get("PATH", ""),
        "COLUMNS": "100",
        "NO_COLOR": "1",
        "TERM": "dumb",
        "PYTHONUNBUFFERED": "1",
    }
    env.pop("FORCE_COLOR", None)
    env.pop("GITHUB_ACTIONS", None)  # lint would switch to GitHub annotations
    done = subprocess.run(
        example.command,
        shell=True,
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=TIMEOUT_S,
    )
    # Paths are shown from the repository root, as the command was typed, whatever the checkout's path.
    text = done.stdout.replace(str(ROOT) + os.sep, "")
    lines = [line.rstrip() for line in text.splitlines()]
    return "$ " + example.command + "\n" + "".join(line + "\n" for line in lines), done.returncode


def masked(text: str) -> str:
    """Numbers and runs of blanks (table column widths follow the numbers) masked."""
    text = re.sub(r"\d[\d,]*(\.\d+)?(e[+-]?\d+)?", "#", text)
    return re.sub(r"[ \t─━┄]+", " ", text)


def same(example: Example, body: str) -> bool:
    return masked(example.body) == masked(body) if example.varies else example.body == body


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    parser.add_argument("--check", action="store_true", help="do not write: exit 1 when a block drifted or failed")
    parser.add_argument("pages", nargs="*", type=Path, help="pages to process (default: README.md and docs/*.md)")
    args = parser.parse_args(argv)
    failed = False
    for page in args.pages or pages():
        page = page if page.is_absolute() else ROOT / page
        found = examples(page)
        if not found:
            continue
        text = page.read_text(encoding="utf-8")
        pieces, last = [], 0
        for example in found:
            body, code = run(example)
            where = f"{page.relative_to(ROOT)}:{text.count(chr(10), 0, example.start)}"
            if code != example.exit_code:
                failed = True
                print(f"{where}: `{example.command}` exited {code}, expected {example.exit_code}:\n{body}")
            elif not same(example, body):
                if args.check:
                    failed = True
                    diff = difflib.unified_diff(
                        example.body.splitlines(), body.splitlines(), "page", "now", lineterm=""
                    )
                    print(f"{where}: the output of `{example.command}` has changed:\n" + "\n".join(diff))
            pieces += [text[last : example.start], body if not same(example, body) else example.body]
            last = example.end
        pieces.append(text[last:])
        new = "".join(pieces)
        if not args.check and new != text:
            page.write_text(new, encoding="utf-8")
            print(f"updated {page.relative_to(ROOT)}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
