"""One step of `make demo` whose exit code is part of what it shows.

    python tools/demo_step.py EXIT "WHAT" [--head N | --tail N] -- COMMAND...

says before it runs what the step is meant to report and the exit code that goes with it
("expect findings, exit 1"), runs COMMAND, and fails (exit 1, with the command and both codes)
unless COMMAND exited with EXIT: a lint step that finds nothing (exit 0) or breaks (exit 2) fails
the demo as loudly as any other step. `--head`/`--tail` show only the first or last N lines of
its standard output; its exit code is checked all the same (a pipe into `head` would hide it).
"""

from __future__ import annotations

import argparse
import shlex
import subprocess
import sys


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("exit", type=int, help="the exit code the step is meant to end with")
    parser.add_argument("what", help="what the step is meant to report (said before it runs)")
    shown = parser.add_mutually_exclusive_group()
    shown.add_argument("--head", type=int, help="show only the first N lines of its output")
    shown.add_argument("--tail", type=int, help="show only the last N lines of its output")
    if "--" not in argv or argv.index("--") == len(argv) - 1:
        parser.error("give the command after --")
    split = argv.index("--")
    args, command = parser.parse_args(argv[:split]), argv[split + 1 :]
    if any(n is not None and n < 1 for n in (args.head, args.tail)):
        parser.error("--head and --tail take a number of lines >= 1")
    print(f"   (expect {args.what}, exit {args.exit})", flush=True)
    print(shlex.join(command), flush=True)
    try:
        if args.head is None and args.tail is None:
            code = subprocess.run(command).returncode
        else:
            done = subprocess.run(command, stdout=subprocess.PIPE, text=True)
            lines = done.stdout.splitlines()
            print("\n".join(lines[: args.head] if args.head is not None else lines[-args.tail :]), flush=True)
            code = done.returncode
    except OSError as exc:
        print(f"demo step FAILED: cannot run `{shlex.join(command)}`: {exc.strerror}", file=sys.stderr)
        return 1
    if code != args.exit:
        print(
            f"demo step FAILED: `{shlex.join(command)}` exited {code}, but it is meant to report "
            f"{args.what} and exit {args.exit}",
            file=sys.stderr,
        )
        return 1
    print(f"-- exit {code}, as expected", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
