"""The manual (README.md and docs/) stays true: its links lead somewhere, its shown output is what
armtool prints today (tools/docs_examples.py), every armtool command line it shows names real
subcommands and options, the site builds, and every command's help links to its page."""

from __future__ import annotations

import importlib.util
import re
import shlex
import subprocess
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
import typer
import typer.main
from typer.testing import CliRunner

from armtool.cli import app
from armtool.docs_links import COMMAND_PAGES, DOCS_URL

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")
FENCE = re.compile(r"^```(\w*)\n(.*?)^```$", re.M | re.S)


def load_tool() -> ModuleType:
    spec = importlib.util.spec_from_file_location("docs_examples", ROOT / "tools" / "docs_examples.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up by name
    spec.loader.exec_module(module)
    return module


def slug(heading: str) -> str:
    """The anchor of a heading as both GitHub and the site (Python-Markdown's toc) write it."""
    text = re.sub(r"[`*_]", "", heading).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return re.sub(r"\s", "-", text)


def anchors(page: Path) -> set[str]:
    text = FENCE.sub("", page.read_text(encoding="utf-8"))
    found = {slug(m.group(1)) for m in re.finditer(r"^#+\s+(.+?)\s*$", text, re.M)}
    return found | set(re.findall(r'<a id="([^"]+)"', text))


def internal_links(page: Path) -> list[tuple[str, Path, str]]:
    """(link as written, the file it names, its anchor) for every relative link outside code."""
    text = FENCE.sub("", page.read_text(encoding="utf-8"))
    text = re.sub(r"`[^`\n]*`", "", text)
    out = []
    for target in LINK.findall(text):
        if re.match(r"[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        out.append((target, (page.parent / path).resolve() if path else page, anchor))
    return out


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_internal_links_lead_somewhere(page: Path) -> None:
    broken = []
    for written, target, anchor in internal_links(page):
        if not target.exists():
            broken.append(f"{written}: no such file")
        elif anchor and target.suffix == ".md" and anchor not in anchors(target):
            broken.append(f"{written}: no heading or anchor '{anchor}' in {target.name}")
    assert not broken, f"{page.relative_to(ROOT)}: " + "; ".join(broken)


def test_shown_output_is_what_armtool_prints() -> None:
    # Every block with a `<!-- run: ... -->` marker is run; a command that fails or prints something
    # else fails here. `python tools/docs_examples.py` rewrites them.
    from armtool.ik.registry import make_solver
    from armtool.model.chain import load_chain

    # The first lm solver of a fresh checkout compiles its kernel and says so on stderr: not in the pages.
    make_solver("lm", load_chain(ROOT / "fixtures/robots/clean_arm/urdf/clean_arm.urdf", "base_link", "tool0"))
    tool = load_tool()
    assert sum(len(tool.examples(page)) for page in PAGES) >= 8  # one per command at least
    assert tool.main(["--check"]) == 0


def command_lines() -> list[tuple[Path, str]]:
    """Every `armtool ...` command line shown in a shell or console block."""
    out = []
    for page in PAGES:
        for lang, body in FENCE.findall(page.read_text(encoding="utf-8")):
            if lang not in ("sh", "bash", "console", "shell", ""):
                continue
            joined = re.sub(r"\\\n\s*", " ", body)
            for line in joined.splitlines():
                line = line.strip().removeprefix("$ ")
                for part in re.split(r"\s*(?:\||&&|;)\s*", line.split(" #")[0]):
                    if part.startswith("armtool "):
                        out.append((page, part))
    return out


def test_every_command_line_names_real_commands_and_options() -> None:
    root = typer.main.get_command(app)
    wrong = []
    for page, line in command_lines():
        try:
            words = shlex.split(line)[1:]
        except ValueError:
            continue  # a line cut by the page's layout
        command: Any = root
        while hasattr(command, "get_command") and words and not words[0].startswith("-"):  # a group
            sub = command.get_command(typer.Context(command), words[0])
            if sub is None:
                wrong.append(f"{page.name}: `{line}`: no command '{words[0]}'")
                break
            command, words = sub, words[1:]
        else:
            known = {opt for param in command.params for opt in (*param.opts, *param.secondary_opts)}
            for word in words:
                name = word.split("=")[0]
                if name.startswith("--") and name not in known:
                    wrong.append(f"{page.name}: `{line}`: {name} is not an option of this command")
    assert len(command_lines()) >= 40
    assert not wrong, "\n".join(wrong)


def test_the_site_builds(tmp_path: Path) -> None:
    pytest.importorskip("mkdocs")
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "site" / "lint" / "index.html").is_file()


@pytest.mark.parametrize("command", [[], *([name] for name in COMMAND_PAGES)], ids=lambda c: " ".join(c) or "armtool")
def test_help_ends_with_a_link_to_its_page(command: list[str]) -> None:
    result = CliRunner().invoke(app, [*command, "--help"], terminal_width=200)
    assert result.exit_code == 0, result.output
    page = COMMAND_PAGES.get(command[0], "index.md") if command else "index.md"
    url = DOCS_URL + page
    assert url in " ".join(result.output.split()), result.output
    assert (ROOT / "docs" / page).is_file()
