"""Expand xacro with the xacro package while remembering where every element came from.

xacro builds a minidom tree without line numbers. We hook two of its functions:
`parse` tags each element of every file it reads with its file and line, and
`handle_macro_call` tags what a macro call produced with the call site. The expanded
document is re-read with lxml and the tags are moved into a side table.

Bounds: xacro evaluates Python expressions (`${str(9**9**9)}`, `${'x'*10**10}`) and reads any
file it is told to include, so a hostile or mistaken xacro could run forever or fill memory.
Expressions are evaluated by `armtool.model.xacro_eval`, which refuses an operation whose result
would be huge before it runs (a single C-level `pow` cannot be interrupted otherwise).
Includes must be regular files of at most MAX_INCLUDE_BYTES (a FIFO or /dev/zero is refused
before it is opened); the expanded document is at most MAX_EXPANDED_CHARS; and where the
platform can fork (and no other thread runs), xacro runs in a forked child with a wall-clock
limit (TIMEOUT_S) and an address-space limit (MEMORY_HEADROOM_BYTES above the parent's size).
A thread cannot be stopped and a SIGALRM cannot interrupt one long C-level call, but a child
can be killed: the last resort for what the expression bounds do not foresee. The fork costs about 1 ms, against tens to hundreds of ms for xacro itself.
"""

from __future__ import annotations

import contextlib
import io
import threading
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lxml import etree

from armtool.fileio import NotRegularFile, read_regular
from armtool.model.display import display_path, included_file_note, note_suffix
from armtool.model.origin import Origin, SourceLine
from armtool.model.packages import PackageResolver
from armtool.model.xacro_eval import bounded_eval
from armtool.model.xmlsource import MAX_FILE_BYTES, XmlSyntaxProblem, declares_entities, parse_xml

SRC_ATTR = "armtool-src"
CALL_ATTR = "armtool-call"
_DIRECTIVES = {
    "xacro:property",
    "xacro:macro",
    "xacro:include",
    "xacro:if",
    "xacro:unless",
    "xacro:arg",
    "xacro:element",
    "xacro:attribute",
    "xacro:insert_block",
    "xacro:call",
}
_LOCK = threading.Lock()

TIMEOUT_S = 60.0  # wall clock for one expansion (the largest real robot here takes well under 2 s)
MAX_INCLUDE_BYTES = MAX_FILE_BYTES  # one file xacro reads (64 MB)
MAX_EXPANDED_CHARS = 128 * 1024 * 1024  # the expanded document
MEMORY_HEADROOM_BYTES = 4 * 1024**3  # address space the child may add to the parent's


class XacroFailure(Exception):
    """xacro could not expand a file. `path:line` is the innermost place in the expanded (top) file
    that leads to the error (the include or macro call, or the element itself); `trail` lists the
    places xacro was at, outermost first (calls and includes through other files)."""

    def __init__(
        self,
        message: str,
        path: Path,
        line: int = 1,
        trail: tuple[SourceLine, ...] = (),
        missing_package: str | None = None,
        missing_arg: str | None = None,
        similar_package: str | None = None,
    ) -> None:
        super().__init__(message)
        self.message = message
        self.path = path
        self.line = line
        self.trail = trail
        self.missing_package = missing_package
        self.missing_arg = missing_arg
        self.similar_package = similar_package  # an existing package whose name is close to the missing one

    @property
    def hint(self) -> str:
        """What the user can pass or change, naming the option that supplies it."""
        if self.missing_package:
            fix = (
                f"write $(find {self.similar_package}) if that is the package meant, or "
                if self.similar_package
                else ""
            )
            return fix + (
                f"pass --package-path DIR (a directory holding package '{self.missing_package}', "
                "found by the <name> in its package.xml) or set ROS_PACKAGE_PATH"
            )
        if self.missing_arg:
            return f"pass --xacro-arg {self.missing_arg}:=VALUE (or give the <xacro:arg> a default)"
        if "/package://" in self.message or "/package:/" in self.message:
            # xacro's get_include_files joins any filename that is not absolute to the including
            # file's directory: it has no package:// scheme (only $(find PKG)).
            return "xacro does not resolve package:// in <xacro:include filename>: write $(find PKG)/path"
        return "fix the xacro, or pass --xacro-arg NAME:=VALUE / --package-path DIR"


class _MissingPackage(Exception):
    """Raised by our $(find) so that the failure names the package (xacro wraps it)."""

    def __init__(self, name: str, similar: str | None = None, where: Path | None = None) -> None:
        place = f", in {display_path(where)}" if where is not None else ""
        maybe = f" (did you mean '{similar}'{place}?)" if similar else ""
        super().__init__(f"package '{name}' not found for $(find {name}){maybe}")
        self.name = name
        self.similar = similar


@dataclass
class Expansion:
    root: etree._Element
    origins: dict[etree._Element, Origin]
    files: list[Path]


def _checked_source(path: Path) -> tuple[Path, etree._Element] | None:
    """Read a file with armtool's safe parser before xacro's parser sees it: entities are refused here.
    None when it cannot be read: xacro then reports the missing include itself, at the including file.
    A FIFO, device or a file over MAX_INCLUDE_BYTES is refused here, before xacro opens it."""
    try:
        data = read_regular(path, MAX_INCLUDE_BYTES + 1)
    except NotRegularFile:
        raise XacroFailure("include is not a regular file (a FIFO, socket or device)", path, 1) from None
    except OSError:
        return None
    if len(data) > MAX_INCLUDE_BYTES:
        raise XacroFailure(f"file is over armtool's limit of {MAX_INCLUDE_BYTES // (1024 * 1024)} MB", path, 1)
    try:
        root = parse_xml(data)
    except XmlSyntaxProblem as exc:
        raise XacroFailure(f"not well-formed XML: {exc.message}", path, exc.line) from None
    if declares_entities(root):
        raise XacroFailure("DOCTYPE declares entities; armtool does not expand them", path, 1)
    return path, root


def _annotate(doc: Any, source: tuple[Path, etree._Element], files: list[Path], directives: dict[Any, str]) -> None:
    """Tag each element with `file index:line`; xacro's own directives (which refuse unknown
    attributes) go into `directives` instead, so that errors inside an include can name its line."""
    path, root = source
    lx_elements = list(root.iter(etree.Element))
    dom_elements = doc.getElementsByTagName("*")
    if len(lx_elements) != len(dom_elements):
        return
    idx = len(files)
    files.append(path)
    for lx, dom in zip(lx_elements, dom_elements):
        if dom.tagName in _DIRECTIVES:
            directives[dom] = f"{idx}:{lx.sourceline}"
            continue
        dom.setAttribute(SRC_ATTR, f"{idx}:{lx.sourceline}")


_FRAMES_ATTR = "_armtool_frames"


def _src_of(node: Any, directives: dict[Any, str]) -> str | None:
    if getattr(node, "nodeType", None) != 1:  # an element
        return None
    src = node.getAttribute(SRC_ATTR)
    return src or directives.get(node)


def _tracked(frames: list[str], src: str | None, fn: Any, *args: Any) -> Any:
    """Run one of xacro's steps with `src` on the stack of places; an exception leaving it carries
    the stack as it was where it was raised (xacro's own stacks have files, not lines)."""
    if src:
        frames.append(src)
    try:
        return fn(*args)
    except Exception as exc:
        if getattr(exc, _FRAMES_ATTR, None) is None:
            with contextlib.suppress(AttributeError):
                setattr(exc, _FRAMES_ATTR, tuple(frames))
        raise
    finally:
        if src:
            frames.pop()


@contextlib.contextmanager
def _hooked(xacro: Any, files: list[Path], resolver: PackageResolver, top: Path) -> Iterator[None]:
    from xacro import substitution_args

    orig_parse = xacro.parse
    orig_call = xacro.handle_macro_call
    orig_eval_all = xacro.eval_all
    orig_include = xacro.process_include
    orig_find = substitution_args._eval_find
    orig_eval = xacro.safe_eval
    directives: dict[Any, str] = {}
    frames: list[str] = []

    def parse(inp: Any, filename: str | None = None) -> Any:
        source = _checked_source(Path(filename).resolve()) if inp is None and filename else None
        doc = orig_parse(inp, filename)
        if source is not None:
            _annotate(doc, source, files, directives)
        return doc

    def eval_all(node: Any, macros: Any, symbols: Any) -> Any:
        return _tracked(frames, _src_of(node, directives), orig_eval_all, node, macros, symbols)

    def process_include(elt: Any, macros: Any, symbols: Any, func: Any) -> Any:
        return _tracked(frames, _src_of(elt, directives), orig_include, elt, macros, symbols, func)

    def handle_macro_call(node: Any, macros: Any, symbols: Any) -> Any:
        src = None
        if node.nodeType == node.ELEMENT_NODE and node.hasAttribute(SRC_ATTR):
            src = node.getAttribute(SRC_ATTR)
            node.removeAttribute(SRC_ATTR)
        parent = node.parentNode
        before = list(parent.childNodes) if parent is not None else []
        done = _tracked(frames, src, orig_call, node, macros, symbols)
        if done and src and parent is not None:
            seen = {id(n) for n in before}
            for child in parent.childNodes:
                if id(child) in seen or child.nodeType != child.ELEMENT_NODE:
                    continue
                for el in [child, *child.getElementsByTagName("*")]:
                    old = el.getAttribute(CALL_ATTR)
                    el.setAttribute(CALL_ATTR, src + (";" + old if old else ""))
        elif not done and src:
            node.setAttribute(SRC_ATTR, src)
        return done

    def eval_find(pkg: str) -> str:
        found = resolver.find(pkg, top.parent)
        if found is None:
            suggestion = resolver.suggest(pkg, top.parent)
            raise _MissingPackage(pkg, suggestion[0] if suggestion else None, suggestion[1] if suggestion else None)
        return str(found)

    xacro.parse = parse
    xacro.handle_macro_call = handle_macro_call
    xacro.eval_all = eval_all
    xacro.process_include = process_include
    substitution_args._eval_find = eval_find
    xacro.safe_eval = bounded_eval
    try:
        yield
    finally:
        xacro.parse = orig_parse
        xacro.handle_macro_call = orig_call
        xacro.eval_all = orig_eval_all
        xacro.process_include = orig_include
        substitution_args._eval_find = orig_find
        xacro.safe_eval = orig_eval


def _parse_loc(value: str, files: list[Path]) -> SourceLine | None:
    idx, _, line = value.partition(":")
    try:
        return SourceLine(files[int(idx)], int(line))
    except (ValueError, IndexError):
        return None


def _message(exc: BaseException) -> str:
    """xacro's message once: its XacroException repeats the wrapped exception (and for $(...) errors
    prefixes the class repr); the wrapped one is shown by itself, then xacro's context suffix."""
    from xacro import XacroException
    from xacro.substitution_args import ArgException

    if isinstance(exc, RecursionError):
        return "macro recursion too deep"
    if not isinstance(exc, XacroException):
        return str(exc) or type(exc).__name__
    inner = exc.exc
    head = str(exc.args[0]) if exc.args and exc.args[0] else ""
    if isinstance(inner, ArgException):
        text = f"undefined substitution argument '{inner}' ($(arg {inner}))"
    elif isinstance(inner, _MissingPackage):
        text = str(inner)
    elif isinstance(inner, OSError) or inner is None:
        text = head or type(exc).__name__
    else:
        inner_text = _message(inner)
        text = inner_text if not head or head.startswith("<class") or inner_text in head else f"{head} {inner_text}"
    macros = [m.body.getAttribute("name") for m in getattr(exc, "macros", None) or () if getattr(m, "body", None)]
    if macros:
        text += f" of macro '{macros[0]}'"
    suffix = " ".join(str(exc.suffix or "").split())
    return f"{text} ({suffix})" if suffix else text


def _cause(exc: BaseException, kind: type[BaseException]) -> BaseException | None:
    seen = 0
    node: BaseException | None = exc
    while node is not None and seen < 20:
        if isinstance(node, kind):
            return node
        node = getattr(node, "exc", None) or node.__cause__ or node.__context__
        seen += 1
    return None


def _failure(exc: BaseException, top: Path, files: list[Path]) -> XacroFailure:
    """One XacroFailure in the file that was expanded: at the innermost include or macro call (or
    element) of that file on the way to the error, with the rest of the way in the message."""
    from xacro.substitution_args import ArgException

    frames = getattr(exc, _FRAMES_ATTR, None) or ()
    trail = tuple(loc for loc in (_parse_loc(f, files) for f in frames) if loc)
    if isinstance(exc, XacroFailure):  # a malformed included file, found by our parser
        message = exc.message
        inner: SourceLine | None = SourceLine(exc.path, exc.line) if exc.path != top else None
        if exc.path == top:
            return exc
    else:
        message = _message(exc)
        inner = trail[-1] if trail and trail[-1].path != top else None
    in_top = [loc for loc in trail if loc.path == top]
    line = in_top[-1].line if in_top else 1
    if inner is not None:
        message += note_suffix(included_file_note(display_path(inner.path), inner.line))
    package = _cause(exc, _MissingPackage)
    arg = _cause(exc, ArgException)
    return XacroFailure(
        message,
        top,
        line,
        trail,
        missing_package=package.name if isinstance(package, _MissingPackage) else None,
        missing_arg=str(arg) if arg is not None else None,
        similar_package=package.similar if isinstance(package, _MissingPackage) else None,
    )


def _expand_text(path: Path, args: Mapping[str, str], resolver: PackageResolver) -> tuple[str, list[Path]]:
    """xacro's output (with our origin attributes) and the files it read, in this process."""
    import xacro

    files: list[Path] = []
    sink = io.StringIO()
    with _hooked(xacro, files, resolver, path), contextlib.redirect_stderr(sink), contextlib.redirect_stdout(sink):
        try:
            doc = xacro.process_file(str(path), mappings=dict(args), verbosity=0)
            text = doc.toxml()
        except Exception as exc:  # xacro raises many types; all become one clear failure
            raise _failure(exc, path, files) from None
        finally:
            with contextlib.suppress(Exception):
                xacro.init_stacks(None)
    if len(text) > MAX_EXPANDED_CHARS:
        raise XacroFailure(
            f"expanded document is over armtool's limit of {MAX_EXPANDED_CHARS // (1024 * 1024)} MB "
            f"({len(text) // (1024 * 1024)} MB)",
            path,
        )
    return text, files


def _can_fork() -> bool:
    import os

    return hasattr(os, "fork") and threading.active_count() == 1  # forking beside threads can deadlock


def _limit_memory() -> None:
    """In the child: its address space may grow by MEMORY_HEADROOM_BYTES, then MemoryError."""
    try:
        import os
        import resource

        with open("/proc/self/statm", "rb") as handle:
            size = int(handle.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        limit = size + MEMORY_HEADROOM_BYTES
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        if hard != resource.RLIM_INFINITY:
            limit = min(limit, hard)
        if soft == resource.RLIM_INFINITY or soft > limit:
            resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    except (OSError, ValueError, ImportError):
        pass  # no /proc or no resource module: the time limit still holds


def _failure_row(exc: XacroFailure) -> tuple[object, ...]:
    return (
        exc.message,
        str(exc.path),
        exc.line,
        tuple((str(loc.path), loc.line) for loc in exc.trail),
        exc.missing_package,
        exc.missing_arg,
        exc.similar_package,
    )


def _failure_from_row(row: tuple[Any, ...]) -> XacroFailure:
    message, path, line, trail, package, arg, similar = row
    return XacroFailure(
        message, Path(path), line, tuple(SourceLine(Path(p), n) for p, n in trail), package, arg, similar
    )


def _expand_forked(path: Path, args: Mapping[str, str], resolver: PackageResolver) -> tuple[str, list[Path]]:
    """_expand_text in a forked child, killed after TIMEOUT_S; its answer comes back through a pipe."""
    import gc
    import marshal
    import os
    import select
    import signal
    import time
    import warnings

    import xacro
    import xacro.substitution_args  # noqa: F401

    read_fd, write_fd = os.pipe()
    pid = -1
    gc.freeze()  # the parent's objects are never collected in the child: their pages stay shared, not copied
    try:
        with warnings.catch_warnings():
            # Python 3.12+ warns when native threads (a BLAS pool in ik-bench) exist at fork; the
            # child runs only xacro and never touches them.
            warnings.filterwarnings("ignore", category=DeprecationWarning, message=".*fork.*")
            pid = os.fork()
    finally:
        if pid != 0:
            gc.unfreeze()
    if pid == 0:  # child: expand, send the answer, never return
        code = 0
        try:
            os.close(read_fd)
            _limit_memory()
            try:
                text, files = _expand_text(path, args, resolver)
                answer: tuple[Any, ...] = ("ok", text, [str(f) for f in files])
            except XacroFailure as exc:
                answer = ("fail", _failure_row(exc))
            except MemoryError:
                answer = ("memory",)
            blob = marshal.dumps(answer)
            view = memoryview(blob)
            while view:
                view = view[os.write(write_fd, view) :]
        except BaseException:
            code = 1
        finally:
            os._exit(code)
    os.close(write_fd)
    chunks: list[bytes] = []
    deadline = time.monotonic() + TIMEOUT_S
    timed_out = False
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                timed_out = True
                break
            ready, _, _ = select.select([read_fd], [], [], left)
            if not ready:
                continue
            chunk = os.read(read_fd, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
    finally:
        os.close(read_fd)
        if timed_out:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        status = 0
        with contextlib.suppress(ChildProcessError):
            status = os.waitpid(pid, 0)[1]
    if timed_out:
        raise XacroFailure(
            f"xacro expansion did not finish within {TIMEOUT_S:g} s (an endless loop or a huge "
            "expression such as 9**9**9?)",
            path,
        )
    reply: list[Any]
    try:
        reply = list(marshal.loads(b"".join(chunks))) if chunks else ["died"]
    except (EOFError, ValueError, TypeError):
        reply = ["died"]  # the child ended mid-answer
    if reply[0] == "died":
        # A child over its memory limit usually raises MemoryError (answered as "memory"); one that
        # ended without an answer is said as it ended, never guessed to be out of memory.
        how = (
            f"was killed by signal {os.WTERMSIG(status)}"
            if os.WIFSIGNALED(status)
            else f"exited with status {os.WEXITSTATUS(status)}"
        )
        raise XacroFailure(f"xacro expansion stopped without an answer (its process {how})", path)
    if reply[0] == "ok":
        return str(reply[1]), [Path(f) for f in reply[2]]
    if reply[0] == "fail":
        raise _failure_from_row(reply[1])
    raise XacroFailure(
        f"xacro expansion ran out of memory (more than {MEMORY_HEADROOM_BYTES // 1024**3} GB: a huge "
        "expression or repetition?)",
        path,
    )


def expand(path: Path, args: Mapping[str, str], resolver: PackageResolver) -> Expansion:
    """Run xacro on `path` within the bounds above; raise XacroFailure with xacro's own message on any error."""
    path = path.resolve()
    with _LOCK:
        if _can_fork():
            text, files = _expand_forked(path, args, resolver)
        else:
            text, files = _expand_text(path, args, resolver)
    try:
        root = parse_xml(text.encode("utf-8"))
    except XmlSyntaxProblem as exc:
        raise XacroFailure(f"expanded document is not well-formed: {exc.message}", path) from None
    origins: dict[etree._Element, Origin] = {}
    for el in root.iter(etree.Element):
        src = el.attrib.pop(SRC_ATTR, None)
        calls = el.attrib.pop(CALL_ATTR, None)
        if src is None and calls is None:
            continue
        call_locs = tuple(loc for loc in (_parse_loc(c, files) for c in (calls or "").split(";") if c) if loc)
        origins[el] = Origin(_parse_loc(src, files) if src else None, call_locs)
    return Expansion(root, origins, files)
