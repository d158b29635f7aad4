"""IEEE 754 binary64 and binary32 on bit patterns, exactly.

The block diagrams of a node model (rule 4.11) carry float constants
written in decimal, and the reference interpreter
(:mod:`pyrosgen.frontend.blocksim`) computes on the values of
``coq/theories/ctrl/Diagram.v``.  Both need numbers to be the very bit
patterns that Coq and the compiled C see, so this module works on bit
patterns (Python ``int``) and rationals (:class:`fractions.Fraction`):

- :func:`round_fraction`: a rational rounded to nearest, ties to even, in
  one step (never through a ``double`` first: rounding a decimal to
  binary64 and then to binary32 can differ from rounding it to binary32,
  see ``tests/frontend/test_blocks.py``), subnormals and overflow to
  infinity included;
- :func:`decimal_bits`: the decimal text of a model number as a float of
  either format;
- :func:`fop`: ``+ - * /`` as ``coq/theories/lib/FloatOps.v`` defines them,
  NaN payloads included (the first NaN operand made quiet, otherwise the
  default NaN ``0xFFF8000000000000`` / ``0xFFC00000``);
- :func:`fcmp`: the IEEE comparisons (a NaN is unordered, ``-0 == +0``).

binary64 arithmetic uses Python's ``float`` (IEEE 754 binary64, rounded to
nearest on every platform CPython supports); binary32 arithmetic is
computed exactly on rationals and rounded once.
"""

from __future__ import annotations

import math
import re
import struct
from fractions import Fraction

__all__ = [
    "FORMATS",
    "Format",
    "F64",
    "F32",
    "fmt",
    "round_fraction",
    "decimal_bits",
    "DecimalError",
    "to_fraction",
    "is_nan",
    "is_zero",
    "is_inf",
    "fneg",
    "fabs",
    "fop",
    "fcmp",
    "as_double",
    "bits_of_double",
    "double_of_bits",
    "default_nan",
]


class Format:
    """A binary interchange format: ``mw`` fraction bits, ``ew`` exponent bits."""

    def __init__(self, name: str, mw: int, ew: int):
        self.name = name
        self.mw = mw
        self.ew = ew
        self.width = mw + ew + 1
        self.bias = (1 << (ew - 1)) - 1
        self.emin = 1 - self.bias            # exponent of the smallest normal
        self.emax = self.bias                # exponent of the largest finite
        self.sign_bit = 1 << (mw + ew)
        self.exp_mask = ((1 << ew) - 1) << mw
        self.frac_mask = (1 << mw) - 1
        self.quiet_bit = 1 << (mw - 1)
        self.inf = self.exp_mask              # +infinity
        #: the largest finite value, as a rational
        self.max_finite = Fraction((1 << (mw + 1)) - 1) * Fraction(2) ** (self.emax - mw)

    def __repr__(self) -> str:
        return f"Format({self.name})"


F64 = Format("float64", 52, 11)
F32 = Format("float32", 23, 8)
FORMATS = {"float64": F64, "float32": F32}


def fmt(prim: str) -> Format:
    """The format of ``float64`` or ``float32``."""
    return FORMATS[prim]


def default_nan(f: Format) -> int:
    """Coq's (and x86-64's) default NaN: negative, quiet, no other payload bit."""
    return f.sign_bit | f.exp_mask | f.quiet_bit


def is_nan(f: Format, b: int) -> bool:
    return (b & f.exp_mask) == f.exp_mask and (b & f.frac_mask) != 0


def is_inf(f: Format, b: int) -> bool:
    return (b & ~f.sign_bit) == f.inf


def is_zero(f: Format, b: int) -> bool:
    return (b & ~f.sign_bit) == 0


def fneg(f: Format, b: int) -> int:
    """The sign bit flipped (NaNs included)."""
    return b ^ f.sign_bit


def fabs(f: Format, b: int) -> int:
    """The sign bit cleared (NaNs included)."""
    return b & ~f.sign_bit


# --------------------------------------------------------------------------
# Rounding


def round_fraction(q: Fraction, negative: bool, f: Format) -> int:
    """The bit pattern of ``(-1)^negative * q`` (``q >= 0`` rational)
    rounded to nearest, ties to even, in format ``f``; beyond the largest
    finite value the result is an infinity, as IEEE 754 rounds."""
    if q < 0:
        raise ValueError("round_fraction: the magnitude must be non-negative")
    sign = f.sign_bit if negative else 0
    if q == 0:
        return sign
    n, d = q.numerator, q.denominator
    # e = floor(log2 q)
    e = n.bit_length() - d.bit_length()
    if (n << max(0, -e)) < (d << max(0, e)):
        e -= 1
    if e < f.emin:
        e = f.emin                            # subnormal: the spacing of the smallest normals
    # m = q / 2^(e - mw), rounded to an integer (at most mw+1 bits)
    shift = f.mw - e
    num, den = (n << shift, d) if shift >= 0 else (n, d << -shift)
    m, rem = divmod(num, den)
    twice = 2 * rem
    if twice > den or (twice == den and m & 1):
        m += 1
    if m == 1 << (f.mw + 1):                  # carried into the next binade
        m >>= 1
        e += 1
    if e > f.emax:
        return sign | f.inf
    if m < 1 << f.mw:                         # subnormal (or zero after rounding: impossible, q > 0 rounds to >= 0)
        return sign | m
    return sign | ((e + f.bias) << f.mw) | (m - (1 << f.mw))


def to_fraction(f: Format, b: int) -> Fraction:
    """The value of a finite pattern (a zero of either sign is 0)."""
    if (b & f.exp_mask) == f.exp_mask:
        raise ValueError("to_fraction: not a finite value")
    e = (b & f.exp_mask) >> f.mw
    m = b & f.frac_mask
    if e == 0:
        v = Fraction(m) * Fraction(2) ** (f.emin - f.mw)
    else:
        v = Fraction(m | (1 << f.mw)) * Fraction(2) ** (e - f.bias - f.mw)
    return -v if b & f.sign_bit else v


class DecimalError(ValueError):
    """A decimal text that is not a finite number of the format."""


#: The decimal numbers of a node model (rule 4.1): sign, digits, an
#: optional fraction and an optional exponent.
_DECIMAL = re.compile(r"([-+]?)([0-9]*)(?:\.([0-9]*))?(?:[eE]([-+]?[0-9]+))?")

#: Longest decimal text read (the exact value of a binary64 subnormal has
#: 767 significant digits; nothing useful is longer).
MAX_DECIMAL_TEXT = 1000


def decimal_bits(text: str, f: Format, scale: Fraction = Fraction(1)) -> int:
    """The decimal ``text`` (``2``, ``-0.5``, ``1.0e-3``) times ``scale``
    (a positive rational from 10^-6 to 10^6; 1 by default), rounded to
    nearest even in format ``f`` from the exact product, once; ``-0.0``
    keeps its sign.  Raises :class:`DecimalError` when the text is not a
    decimal number or the result rounds to an infinity."""
    if not Fraction(1, 10**6) <= scale <= 10**6:
        raise ValueError("decimal_bits: scale out of range")
    if len(text) > MAX_DECIMAL_TEXT:
        raise DecimalError(f"is too long ({len(text)} characters)")
    mt = _DECIMAL.fullmatch(text)
    if not mt or not (mt.group(2) or mt.group(3)):
        raise DecimalError("is not a decimal number")
    negative = mt.group(1) == "-"
    whole, frac, exp = mt.group(2), mt.group(3) or "", mt.group(4)
    digits = (whole + frac).lstrip("0")
    if not digits:
        return f.sign_bit if negative else 0
    e10 = (int(exp) if exp is not None and len(exp) < 12 else (0 if exp is None else None))
    if e10 is None:                          # an exponent of 12 digits or more
        if exp.startswith("-"):
            return f.sign_bit if negative else 0
        raise DecimalError(f"is out of the range of {f.name}")
    e10 -= len(frac)
    magnitude = len(digits) + e10            # 10^(magnitude-1) <= value < 10^magnitude
    if magnitude > 400:                      # even times 10^-6, above the largest finite
        raise DecimalError(f"is out of the range of {f.name}")
    if magnitude < -400:                     # even times 10^6, below half the smallest subnormal
        return f.sign_bit if negative else 0
    q = Fraction(int(digits)) * Fraction(10) ** e10 * scale
    b = round_fraction(q, negative, f)
    if is_inf(f, b):
        raise DecimalError(f"is out of the range of {f.name} (it rounds to infinity)")
    return b


# --------------------------------------------------------------------------
# Arithmetic and comparisons (coq/theories/lib/FloatOps.v, clight/Operators.v)


def double_of_bits(b: int) -> float:
    """The Python float of a binary64 pattern (NaN payloads are kept)."""
    return struct.unpack("<d", struct.pack("<Q", b))[0]


def bits_of_double(x: float) -> int:
    """The binary64 pattern of a Python float."""
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def _nan_of(f: Format, x: int, y: int) -> int:
    """FloatOps.nan_of: the first NaN operand made quiet, else the default NaN."""
    if is_nan(f, x):
        return x | f.quiet_bit
    if is_nan(f, y):
        return y | f.quiet_bit
    return default_nan(f)


def _special(f: Format, op: str, x: int, y: int) -> int | None:
    """The IEEE result of ``x op y`` when an operand is a NaN or an
    infinity, or the operation divides by zero; ``None`` otherwise."""
    if is_nan(f, x) or is_nan(f, y):
        return _nan_of(f, x, y)
    xs, ys = bool(x & f.sign_bit), bool(y & f.sign_bit)
    xi, yi = is_inf(f, x), is_inf(f, y)
    xz, yz = is_zero(f, x), is_zero(f, y)
    if op in "+-":
        if op == "-":
            ys = not ys
        if xi and yi and xs != ys:
            return _nan_of(f, x, y)          # inf - inf
        if xi:
            return x
        if yi:
            return (f.sign_bit if ys else 0) | f.inf
        return None
    s = f.sign_bit if xs != ys else 0
    if op == "*":
        if xi or yi:
            return _nan_of(f, x, y) if (xz or yz) else s | f.inf
        return None
    # division
    if xi and yi:
        return _nan_of(f, x, y)
    if xi:
        return s | f.inf
    if yi:
        return s
    if yz:
        return _nan_of(f, x, y) if xz else s | f.inf
    return None


def fop(f: Format, op: str, x: int, y: int) -> int:
    """``x op y`` (``op`` one of ``+ - * /``) on patterns of format ``f``,
    rounded to nearest even, NaNs as FloatOps chooses them."""
    if op not in ("+", "-", "*", "/"):
        raise ValueError(f"fop: unknown operator {op!r}")
    sp = _special(f, op, x, y)
    if sp is not None:
        return sp
    if f is F64:
        a, b = double_of_bits(x), double_of_bits(y)
        r = a + b if op == "+" else a - b if op == "-" else a * b if op == "*" else a / b
        if math.isnan(r):  # pragma: no cover - NaNs come from _special only
            return _nan_of(f, x, y)
        return bits_of_double(r)
    a, b = to_fraction(f, x), to_fraction(f, y)
    if op == "+":
        r = a + b
    elif op == "-":
        r = a - b
    elif op == "*":
        r = a * b
    else:
        r = a / b
    if r == 0:
        # an exact zero: the sign of a product or quotient is the xor of
        # the signs; a sum of opposite values is +0 (to nearest), of two
        # zeros of the same sign that sign
        xs, ys = bool(x & f.sign_bit), bool(y & f.sign_bit)
        if op in "*/":
            return f.sign_bit if xs != ys else 0
        if op == "-":
            ys = not ys
        if is_zero(f, x) and is_zero(f, y) and xs == ys:
            return f.sign_bit if xs else 0
        return 0
    return round_fraction(abs(r), r < 0, f)


def fcmp(f: Format, op: str, x: int, y: int) -> bool:
    """``x op y`` (``== != < <= > >=``) as IEEE 754 compares: a NaN is
    unordered (only ``!=`` holds), ``-0 == +0``."""
    if is_nan(f, x) or is_nan(f, y):
        return op == "!="
    return _ICMP[op](as_double(f, x), as_double(f, y))


def as_double(f: Format, b: int) -> float:
    """The value of a pattern as a Python float (exact: every binary32
    value is a binary64 value; a binary32 NaN's payload is not kept)."""
    if f is F64:
        return double_of_bits(b)
    return struct.unpack("<f", struct.pack("<I", b))[0]


_ICMP = {
    "==": lambda a, b: a == b,
    "!=": lambda a, b: a != b,
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
}
