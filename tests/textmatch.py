"""Compare printed text across machines: the words exactly, the numbers within a stated tolerance.

A number computed on another CPU can differ in its last bit (other SIMD kernels, another order of
a sum), so the 16th digit of a ``repr`` and, rarely, the last digit of a rounded value change from
machine to machine. Text that holds numbers is therefore compared token by token:

- everything that is not a number must be identical;
- two numbers match when they agree to a relative tolerance (:data:`REL_TOL`), or, for rounded
  numbers (a decimal point or an exponent, at least three significant digits), when they differ by
  at most one unit in their last printed digit (a value on a rounding boundary rounds either way).
  Integers and numbers of one or two digits (counts, options, inputs echoed) must be equal.

The numbers' printed form (digits, exponent) is not compared: ``6.37e-06`` and ``6.38e-06`` match,
``6.37e-06`` and ``6.39e-06`` do not.
"""

from __future__ import annotations

import math
import re

__all__ = ["REL_TOL", "same_numbers", "same_text"]

#: Relative tolerance between two numbers printed to full precision (a few ulps of a leak rate).
REL_TOL = 1e-9

_NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def _last_digit_unit(token: str) -> float:
    """One unit in the last printed digit of a rounded number (``6.37e-06`` -> 1e-08); 0 for an integer
    or a number of fewer than three significant digits, which must match exactly."""
    mantissa, _, exponent = token.lower().lstrip("+-").partition("e")
    if "." not in mantissa and not exponent:
        return 0.0
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    if len(mantissa.replace(".", "").lstrip("0")) < 3:
        return 0.0
    return 10.0 ** (int(exponent or 0) - decimals)


def same_numbers(a: str, b: str) -> bool:
    """Whether two printed numbers are the same value, up to the machine-to-machine differences above."""
    x, y = float(a), float(b)
    if x == y or math.isclose(x, y, rel_tol=REL_TOL, abs_tol=0.0):
        return True
    unit = min(_last_digit_unit(a), _last_digit_unit(b))
    return abs(x - y) <= unit * (1 + 1e-9)


def same_text(a: str, b: str) -> bool:
    """Whether two lines (or texts) are equal: the text between numbers exactly, the numbers by :func:`same_numbers`."""
    if a == b:
        return True
    words_a, words_b = _NUMBER.split(a), _NUMBER.split(b)
    nums_a, nums_b = _NUMBER.findall(a), _NUMBER.findall(b)
    return words_a == words_b and len(nums_a) == len(nums_b) and all(map(same_numbers, nums_a, nums_b))
