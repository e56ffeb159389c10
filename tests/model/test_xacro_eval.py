"""xacro expressions with bounded operations: huge results are refused before they are computed,
everything else evaluates as xacro evaluates it."""

from __future__ import annotations

import time
from typing import Any

import pytest

from armtool.model.xacro_eval import ExpressionTooLarge, bounded_eval


def _symbols() -> dict[str, Any]:
    import xacro

    return dict(xacro.create_global_symbols())


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("2**3 + int('7') * 2", 22),
        ("[1, 2] * 3", [1, 2, 1, 2, 1, 2]),
        ("'ab' * 3", "ababab"),
        ("3 * 'ab'", "ababab"),
        ("2 ** 0.5", 2**0.5),
        ("(-2) ** 3", -8),
        ("2 ** -2", 0.25),
        ("1 << 10", 1024),
        ("pi * 0.5", 1.5707963267948966),
        ("math.factorial(5) + math.comb(5, 2)", 130),
        ("math.prod([2, 3, 4])", 24),
        ("python.sum(x * x for x in python.range(4))", 14),
        ("len(python.range(0, 10, 3))", 4),
        ("max(1, 2) if True else 0", 2),
    ],
)
def test_ordinary_expressions_evaluate_as_in_xacro(expr: str, expected: object) -> None:
    import xacro

    assert bounded_eval(expr, _symbols()) == expected == xacro.safe_eval(expr, _symbols())


@pytest.mark.parametrize(
    ("expr", "says"),
    [
        ("9**9**9", "9 ** 387420489 would have about 1.23e+09 bits"),
        ("str(10**10**8)", "10 ** 100000000"),
        ("1 << 10**10", "<< 10000000000"),
        ("'x' * 10**10", "repeating a str of length 1 10000000000 times"),
        ("[0] * 10**9", "repeating a list"),
        ("(2**60000) * (2**60000)", "product of"),
        ("math.factorial(10**8)", "math.factorial(100000000"),
        ("python.sum(python.range(10**12))", "range of 1e+12 numbers"),
        ("math.prod(python.range(1, 10**6))", "product of"),
    ],
)
def test_huge_results_are_refused_before_they_are_computed(expr: str, says: str) -> None:
    start = time.monotonic()
    with pytest.raises(ExpressionTooLarge, match="armtool") as info:
        bounded_eval(expr, _symbols())
    assert says in str(info.value)
    assert time.monotonic() - start < 2


def test_xacros_own_rule_on_dunder_names_still_holds() -> None:
    from xacro import XacroException

    with pytest.raises(XacroException, match="invalid name"):
        bounded_eval("().__class__", _symbols())
    with pytest.raises(XacroException, match="invalid name"):
        bounded_eval("__armtool_pow(9, 9)", _symbols())
