"""xacro's `${...}` expressions, evaluated with their size bounded before each operation runs.

xacro evaluates Python expressions with `eval`. One operation such as `9**9**9` (a number of
about 1.2 billion bits) or `'x' * 10**10` is a single C-level call: neither a SIGALRM nor a
thread can stop it, and a forked child only ends when its time limit kills it. So the
expression is rewritten before it runs: every `**`, `<<`, `*` and call goes through a guard
that works out the size of the result from the operands (the bit length of a power, the length
of a repetition, the length of a range, the argument of a factorial) and refuses one that no
robot description needs, with a message that names the operation. The expression's meaning is
unchanged otherwise: the guards call the same operator on the same values.

xacro's own rules stay: names starting with `__` are refused (checked on the expression as
written), and the only builtins are the guards themselves.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable, Sized
from functools import lru_cache
from typing import Any

# Far beyond any real description (a joint angle, a mesh scale, a repeated name), far below
# what takes noticeable time or memory to compute.
MAX_INT_BITS = 1 << 16  # 65,536 bits: about 19,700 decimal digits
MAX_LENGTH = 10_000_000  # items or characters of a repeated sequence or a range
MAX_FACTORIAL = 10_000  # math.factorial, comb, perm: their first argument

_POW = "__armtool_pow"
_LSHIFT = "__armtool_lshift"
_MUL = "__armtool_mul"
_CALL = "__armtool_call"


class ExpressionTooLarge(ValueError):
    """An operation in a xacro expression whose result would be too large to compute."""


def _int_like(value: object) -> bool:
    return isinstance(value, int)  # bool included: True ** n is 1


def _bits(value: int) -> int:
    return abs(value).bit_length()


def _pow(base: Any, exponent: Any) -> Any:
    if _int_like(base) and _int_like(exponent) and exponent > 0 and abs(base) > 1:
        bits = exponent * math.log2(abs(base))
        if bits > MAX_INT_BITS:
            raise ExpressionTooLarge(
                f"{_short(base)} ** {_short(exponent)} would have about {bits:.3g} bits "
                f"(armtool evaluates at most {MAX_INT_BITS} bits)"
            )
    return base**exponent


def _lshift(value: Any, shift: Any) -> Any:
    if _int_like(value) and _int_like(shift) and value != 0 and _bits(value) + shift > MAX_INT_BITS:
        raise ExpressionTooLarge(
            f"{_short(value)} << {_short(shift)} would have about {_bits(value) + shift:.3g} bits "
            f"(armtool evaluates at most {MAX_INT_BITS} bits)"
        )
    return value << shift


def _mul(left: Any, right: Any) -> Any:
    for seq, count in ((left, right), (right, left)):
        if isinstance(seq, (str, bytes, list, tuple)) and _int_like(count) and len(seq) * count > MAX_LENGTH:
            raise ExpressionTooLarge(
                f"repeating a {type(seq).__name__} of length {len(seq)} {_short(count)} times would give "
                f"{len(seq) * count:.3g} items (armtool allows at most {MAX_LENGTH})"
            )
    if _int_like(left) and _int_like(right) and _bits(left) + _bits(right) > MAX_INT_BITS:
        raise ExpressionTooLarge(
            f"a product of {_bits(left)}-bit and {_bits(right)}-bit numbers (armtool evaluates at most "
            f"{MAX_INT_BITS} bits)"
        )
    return left * right


def _call(function: Any, *args: Any, **kwargs: Any) -> Any:
    if function is range:
        span = range(*args, **kwargs)  # lazy: its length is known without making the items
        if len(span) > MAX_LENGTH:
            raise ExpressionTooLarge(f"range of {len(span):.3g} numbers (armtool allows at most {MAX_LENGTH})")
        return span
    if function in (math.factorial, math.comb, math.perm) and args and _int_like(args[0]):
        if args[0] > MAX_FACTORIAL:
            raise ExpressionTooLarge(
                f"math.{function.__name__}({_short(args[0])}, ...) (armtool allows arguments up to {MAX_FACTORIAL})"
            )
    if function is pow and len(args) == 2:
        return _pow(*args)
    if function is math.prod and not kwargs and len(args) == 1:
        product: Any = 1
        for item in args[0]:  # one guarded step at a time: prod(range(1, 10**6)) is a factorial
            product = _mul(product, item)
        return product
    if function is math.lcm and not kwargs and sum(_bits(a) for a in args if _int_like(a)) > MAX_INT_BITS:
        raise ExpressionTooLarge(f"math.lcm of {len(args)} numbers (armtool evaluates at most {MAX_INT_BITS} bits)")
    return function(*args, **kwargs)


def _short(value: Any) -> str:
    """A number as it can be shown in a message: huge ones by their size, not their digits."""
    if _int_like(value) and _bits(value) > 64:
        return f"<a {_bits(value)}-bit number>"
    if isinstance(value, Sized) and not isinstance(value, (str, bytes)):
        return f"<{type(value).__name__} of length {len(value)}>"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


GUARDS: dict[str, Callable[..., Any]] = {_POW: _pow, _LSHIFT: _lshift, _MUL: _mul, _CALL: _call}
_BINARY = {ast.Pow: _POW, ast.LShift: _LSHIFT, ast.Mult: _MUL}


class _Bound(ast.NodeTransformer):
    """`a ** b` -> `__armtool_pow(a, b)` (and <<, *); `f(x)` -> `__armtool_call(f, x)`."""

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        guard = _BINARY.get(type(node.op))
        if guard is None:
            return node
        return ast.Call(ast.Name(guard, ast.Load()), [node.left, node.right], [])

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        return ast.Call(ast.Name(_CALL, ast.Load()), [node.func, *node.args], node.keywords)


@lru_cache(maxsize=4096)
def _compiled(expr: str) -> tuple[Any, tuple[str, ...]]:
    """The bounded code of `expr` and the names the expression as written uses (xacro checks those)."""
    plain = compile(expr, "<expression>", "eval")
    tree = _Bound().visit(ast.parse(expr, "<expression>", "eval"))
    ast.fix_missing_locations(tree)
    return compile(tree, "<expression>", "eval"), tuple(plain.co_names)


def bounded_eval(expr: str, globals_: dict[str, Any], locals_: Any = None) -> Any:
    """A drop-in for xacro's `safe_eval`: the same checks, the same result, bounded operations."""
    from xacro import XacroException

    code, names = _compiled(expr.strip())
    invalid = [n for n in names if n.startswith("__")]
    if invalid:
        raise XacroException("Use of invalid name(s): ", ", ".join(invalid))
    globals_.update(__builtins__=dict(GUARDS))  # xacro's empty builtins, plus the guards
    return eval(code, globals_, locals_)  # xacro's own evaluation, bounded as above


__all__ = ["ExpressionTooLarge", "bounded_eval"]
