"""The ecosystem check (STYLE.md, after ruff-ecosystem): lint every package of the real-world corpus
(../shared/realworld beside the checkout) with the lint commands its cases.yaml lists, write every
finding to a snapshot, and compare it with the baseline committed in tests/ecosystem/baseline.json.
A rule change is judged by this diff: the findings it adds and removes, per rule.

    python tools/ecosystem.py                 # compare; exit 1 when the findings differ
    python tools/ecosystem.py --update        # rewrite the baseline with today's findings
    python tools/ecosystem.py --snapshot OUT  # also write today's snapshot to OUT

Each case runs as score.py runs it (the corpus as working directory, `--package-path` for each of
its `package_path` entries, `--format json`, no ROS environment), but in this process: one start-up
for all cases. Findings are stored machine-independently: paths relative to the corpus, and the
corpus, the checkout and the Python prefix written as <corpus>, <armtool> and <python> in messages.
"""

from __future__ import annotations

import argparse
import collections
import importlib.util
import json
import os
import sys
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType
from typing import Any, NamedTuple

ROOT = Path(__file__).resolve().parents[1]
CORPUS = (ROOT / ".." / "shared" / "realworld").resolve()
BASELINE = ROOT / "tests" / "ecosystem" / "baseline.json"
LINT_COMMANDS = ("lint", "lint-urdf")
ROS_ENV = ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH", "CMAKE_PREFIX_PATH", "GITHUB_ACTIONS")
SCHEMA = 1


class Outcome(NamedTuple):
    """One case's run: its exit code, stdout and stderr (a traceback appended when it raised)."""

    exit_code: int
    stdout: str
    stderr: str


def score_module(corpus: Path = CORPUS) -> ModuleType:
    """The corpus's own score.py, imported: cases are built and judged exactly as it does."""
    spec = importlib.util.spec_from_file_location("realworld_score", corpus / "score.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def lint_cases(corpus: Path = CORPUS) -> list[dict[str, Any]]:
    import yaml

    every = yaml.safe_load((corpus / "cases.yaml").read_text(encoding="utf-8"))
    return [c for c in every if str(c["cmd"][0]) in LINT_COMMANDS]


@contextmanager
def _in_corpus(corpus: Path) -> Iterator[None]:
    """The corpus as working directory and no ROS environment, as score.py runs a case."""
    saved_cwd = os.getcwd()
    saved_env = {var: os.environ.pop(var) for var in ROS_ENV if var in os.environ}
    os.chdir(corpus)
    try:
        yield
    finally:
        os.chdir(saved_cwd)
        os.environ.update(saved_env)


def run_case(case: dict[str, Any], score: ModuleType, corpus: Path = CORPUS) -> Outcome:
    """The case's lint command run in this process."""
    from typer.testing import CliRunner

    from armtool.cli import app

    with _in_corpus(corpus):
        argv = score.build_cmd([], case, str(corpus))
        result = CliRunner().invoke(app, argv)
    from armtool.errors import ArmtoolError

    err, exit_code = result.stderr, int(result.exit_code)
    if isinstance(result.exception, ArmtoolError):  # what armtool.cli.main does with it: exit 2, said on stderr
        err, exit_code = err + f"error: {result.exception}\n", 2
    elif result.exception is not None and not isinstance(result.exception, SystemExit):
        err += f"\nTraceback (most recent call last): {type(result.exception).__name__}: {result.exception}"
    return Outcome(exit_code, result.stdout, err)


def _portable(text: str, corpus: Path) -> str:
    """A message without this machine's directories: paths in the corpus relative to it."""
    text = text.replace(str(corpus) + os.sep, "")
    for prefix, name in ((corpus, "<corpus>"), (Path(sys.prefix).resolve(), "<python>"), (ROOT, "<armtool>")):
        text = text.replace(str(prefix), name)
    return text


def case_snapshot(case: dict[str, Any], outcome: Outcome, score: ModuleType, corpus: Path = CORPUS) -> dict[str, Any]:
    """One case's entry: its exit code and every finding (file, line, code, severity, message),
    sorted; `crash` when the run did not end as a lint run (exit 2, traceback, no JSON)."""
    entry: dict[str, Any] = {"exit": outcome.exit_code}
    findings: list[list[Any]] = []
    try:
        doc = json.loads(outcome.stdout)
        rows = doc["findings"] if isinstance(doc, dict) else doc
    except (ValueError, KeyError, TypeError):
        rows = []
        entry["crash"] = _portable(outcome.stderr.strip()[-300:], corpus)
    if "Traceback (most recent call last)" in outcome.stderr:
        entry["crash"] = _portable(outcome.stderr.strip().splitlines()[-1][:300], corpus)
    for f in rows:
        file = score.norm_path(str(f.get("path", "")), str(corpus))
        findings.append(
            [_portable(file, corpus), f["line"], f["code"], f["severity"], _portable(str(f["message"]), corpus)]
        )
    entry["findings"] = sorted(findings, key=lambda r: (r[0], r[1], r[2], r[4]))
    return entry


def snapshot(
    outcomes: Iterable[tuple[dict[str, Any], Outcome]], score: ModuleType, corpus: Path = CORPUS
) -> dict[str, Any]:
    return {
        "schema": SCHEMA,
        "cases": {case["id"]: case_snapshot(case, outcome, score, corpus) for case, outcome in outcomes},
    }


def _rows(snap: dict[str, Any]) -> collections.Counter[tuple[Any, ...]]:
    out: collections.Counter[tuple[Any, ...]] = collections.Counter()
    for case_id, entry in snap.get("cases", {}).items():
        for row in entry.get("findings", []):
            out[tuple([case_id, *row])] += 1
    return out


def compare(baseline: dict[str, Any], current: dict[str, Any]) -> list[str]:
    """The differences, as lines for people: per rule the findings added (+) and removed (-), then
    cases whose exit code or crash changed, or that appeared or disappeared. Empty when equal."""
    old, new = _rows(baseline), _rows(current)
    added, removed = new - old, old - new
    by_rule: dict[str, list[str]] = collections.defaultdict(list)
    counts: dict[str, list[int]] = collections.defaultdict(lambda: [0, 0])
    for sign, rows in (("+", added), ("-", removed)):
        for (case_id, file, line, code, severity, message), n in sorted(rows.items()):
            counts[code][sign == "-"] += n
            for _ in range(n):
                by_rule[code].append(f"  {sign} {case_id}: {file}:{line} {severity} {message}")
    lines: list[str] = []
    for code in sorted(by_rule):
        plus, minus = counts[code]
        lines.append(f"{code}: +{plus} -{minus}")
        lines += by_rule[code]
    old_cases, new_cases = baseline.get("cases", {}), current.get("cases", {})
    for case_id in sorted(set(old_cases) | set(new_cases)):
        before, after = old_cases.get(case_id), new_cases.get(case_id)
        if before is None or after is None:
            lines.append(f"case {case_id}: {'added' if before is None else 'removed'}")
            continue
        for key in ("exit", "crash"):
            if before.get(key) != after.get(key):
                lines.append(f"case {case_id}: {key} {before.get(key)!r} -> {after.get(key)!r}")
    return lines


def dump(snap: dict[str, Any]) -> str:
    """The snapshot as committed: one finding per line, so a change shows as a readable git diff."""
    out = ['{"schema": ' + str(snap["schema"]) + ', "cases": {']
    items = sorted(snap["cases"].items())
    for i, (case_id, entry) in enumerate(items):
        head = {k: v for k, v in entry.items() if k != "findings"}
        out.append(f"  {json.dumps(case_id)}: {{")
        for key, value in head.items():
            out.append(f"    {json.dumps(key)}: {json.dumps(value, ensure_ascii=False)},")
        rows = entry["findings"]
        if not rows:
            out.append('    "findings": []')
        else:
            out.append('    "findings": [')
            out += [
                f"      {json.dumps(r, ensure_ascii=False)}{',' if j < len(rows) - 1 else ''}"
                for j, r in enumerate(rows)
            ]
            out.append("    ]")
        out.append("  }" + ("," if i < len(items) - 1 else ""))
    out.append("}}")
    return "\n".join(out) + "\n"


def load_baseline(path: Path = BASELINE) -> dict[str, Any]:
    if not path.is_file():
        return {"schema": SCHEMA, "cases": {}}
    data: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    return data


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--corpus", type=Path, default=CORPUS, help="the corpus (default: ../shared/realworld)")
    ap.add_argument("--baseline", type=Path, default=BASELINE, help="the committed baseline")
    ap.add_argument("--update", action="store_true", help="rewrite the baseline with today's findings")
    ap.add_argument("--snapshot", type=Path, help="also write today's snapshot here")
    ap.add_argument("--case", action="append", default=[], help="only cases whose id contains this (repeatable)")
    a = ap.parse_args(argv)
    corpus = a.corpus.resolve()
    if not (corpus / "cases.yaml").is_file():
        print(f"error: no cases.yaml in {corpus}", file=sys.stderr)
        return 2
    score = score_module(corpus)
    cases = [c for c in lint_cases(corpus) if not a.case or any(s in c["id"] for s in a.case)]
    current = snapshot(((c, run_case(c, score, corpus)) for c in cases), score, corpus)
    baseline = load_baseline(a.baseline)
    if a.case:  # compare only the cases that ran
        baseline = {"schema": SCHEMA, "cases": {k: v for k, v in baseline["cases"].items() if k in current["cases"]}}
    if a.snapshot:
        a.snapshot.write_text(dump(current), encoding="utf-8")
    total = sum(len(e["findings"]) for e in current["cases"].values())
    if a.update:
        if a.case:
            merged = load_baseline(a.baseline)
            merged["cases"].update(current["cases"])
            current = merged
        a.baseline.parent.mkdir(parents=True, exist_ok=True)
        a.baseline.write_text(dump(current), encoding="utf-8")
        print(f"ecosystem: baseline rewritten: {len(current['cases'])} cases, {total} findings -> {a.baseline}")
        return 0
    diff = compare(baseline, current)
    for line in diff:
        print(line)
    print(
        f"ecosystem: {len(cases)} cases, {total} findings, "
        + (f"{len(diff)} lines of difference" if diff else "same as the baseline")
    )
    return 1 if diff else 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main())
