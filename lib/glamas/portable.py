"""Elementary functions that give the same bits on every processor.

numpy chooses the machine code of ``np.log10``, ``np.log2``, ``np.power``, ``np.exp``, ``np.log``,
``np.sin`` and ``np.cos`` by the processor it runs on: with AVX-512 it calls vector routines of
its own or Intel's SVML, without it the C library. The two differ in the last bit for some inputs,
so a log axis placed a label 1e-13 pt apart on two machines and a figure's bytes depended on the
processor. The functions here are written with nothing but IEEE-754 arithmetic (+, -, *, / and
exact scalings by powers of two, which every processor rounds alike), after fdlibm's algorithms
(Sun's freely distributable libm, as in FreeBSD's msun): the same inputs give the same bits
everywhere. Their error is within a few units in the last place, far below anything drawn or
printed.

Used wherever a value reaches a figure or a verdict: the log scales of every figure
(:mod:`glamas.plotting` registers its portable log scale under matplotlib's name ``"log"``), the
log-spaced block edges and checkpoints the kernels read (:func:`geomspace`), and the analyses'
fits and directions. The compiled kernels do not use them: numba calls the C library, the same on
every machine with the same library, and ``tests/test_portable_results.py`` recomputes one small
result of each experiment against digests committed beside the results, so that a processor that
gives other bits is found (docs/speed.md, "What is portable").
"""

import math

import numpy as np
from numba import njit, vectorize

# fdlibm e_log.c
_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
_LG = (6.666666666666735130e-01, 3.999999999940941908e-01, 2.857142874366239149e-01, 2.222219843214978396e-01,
       1.818357216161805012e-01, 1.531383769920937332e-01, 1.479819860511658591e-01)
# fdlibm e_log10.c (log10_2hi has its last 13 bits zero: k * log10_2hi is exact for |k| < 2**13)
_IVLN10 = 4.34294481903251816668e-01
_LOG10_2HI = 3.01029995663611771306e-01
_LOG10_2LO = 3.69423907715893078616e-13
_IVLN2 = 1.44269504088896338700e+00
_LN10 = 2.30258509299404568402e+00
_LN2 = 6.93147180559945286227e-01
_LOG2_10 = 3.32192809488736234787e+00
# fdlibm e_exp.c
_P = (1.66666666666666019037e-01, -2.77777777770155933842e-03, 6.61375632143793436117e-05,
      -1.65339022054652515390e-06, 4.13813679705723846039e-08)
_EXP_HIGH, _EXP_LOW = 7.09782712893383973096e+02, -7.45133219101941108420e+02
# fdlibm k_sin.c and k_cos.c (FreeBSD's form of the cosine's last step)
_S = (-1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04,
      2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10)
_C = (4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05,
      -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11)
_TWO_PI = 6.28318530717958647692e+00

_POW10_FROM = -323
_POW10 = np.array([float(f"1e{k}") for k in range(_POW10_FROM, 309)])
"""The double nearest 10**k for every k a double reaches (reading a decimal rounds correctly)."""


@njit(cache=True)
def _horner(z, c):
    """c[0] + z (c[1] + z (c[2] + ...)), one rounding per operation, in this order."""
    total = c[-1]
    for i in range(len(c) - 2, -1, -1):
        total = c[i] + z * total
    return total


@njit(cache=True)
def _split(x):
    """x = m * 2**k with m in [sqrt(1/2), sqrt(2)) (exact), for finite x > 0: (f = m - 1, k)."""
    m, k = math.frexp(x)  # m in [1/2, 1)
    if m < 0.7071067811865476:
        return 2.0 * m - 1.0, float(k - 1)  # m - 1 is exact for m in [1/2, 2]
    return m - 1.0, float(k)


@njit(cache=True)
def _log1p_of_split(f):
    """ln(1 + f) for f = m - 1 of :func:`_split` (fdlibm's log, its polynomial in s = f / (2 + f))."""
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    t1 = w * _horner(w, (_LG[1], _LG[3], _LG[5]))
    t2 = z * _horner(w, (_LG[0], _LG[2], _LG[4], _LG[6]))
    hfsq = 0.5 * f * f
    return f - (hfsq - s * (hfsq + (t2 + t1)))


@njit(cache=True)
def _edge_of_log(x):
    """A logarithm's value where x is not finite and positive: -inf at 0, +inf at +inf, else NaN."""
    return -np.inf if x == 0.0 else (np.inf if x == np.inf else np.nan)


@njit(cache=True)
def _log(x):
    if not (0.0 < x < np.inf):
        return _edge_of_log(x)
    f, k = _split(x)
    return k * _LN2_HI + (k * _LN2_LO + _log1p_of_split(f))


@njit(cache=True)
def _log10(x):
    if not (0.0 < x < np.inf):
        return _edge_of_log(x)
    f, k = _split(x)
    y = k * _LOG10_2HI + (k * _LOG10_2LO + _IVLN10 * _log1p_of_split(f))
    whole = np.rint(y)
    at = int(min(max(whole - _POW10_FROM, 0.0), _POW10.size - 1.0))
    return whole if _POW10[at] == x else y


@njit(cache=True)
def _log2(x):
    if not (0.0 < x < np.inf):
        return _edge_of_log(x)
    f, k = _split(x)
    return k + _IVLN2 * _log1p_of_split(f)


@njit(cache=True)
def _exp_reduced(r, hi, lo):
    """exp(r) for |r| <= ln(2) / 2, r = hi - lo (fdlibm's polynomial and its last step)."""
    t = r * r
    c = r - t * _horner(t, _P)
    return 1.0 - ((lo - (r * c) / (2.0 - c)) - hi)


@njit(cache=True)
def _exp(x):
    if x != x:
        return np.nan
    if x > _EXP_HIGH:
        return np.inf
    if x < _EXP_LOW:
        return 0.0
    k = np.rint(x * _IVLN2)
    hi = x - k * _LN2_HI  # exact: ln2_hi has its last 32 bits zero
    lo = k * _LN2_LO
    return math.ldexp(_exp_reduced(hi - lo, hi, lo), int(k))


@njit(cache=True)
def _power10(y):
    if y != y:
        return np.nan
    if y == np.inf:
        return np.inf
    if y == -np.inf:
        return 0.0
    safe = min(max(y, -330.0), 310.0)
    if safe == np.rint(safe) and _POW10_FROM <= safe < _POW10_FROM + _POW10.size:
        return _POW10[int(safe - _POW10_FROM)]
    if safe > 308.3:
        return np.inf
    k = np.rint(safe * _LOG2_10)
    r = (safe - k * _LOG10_2HI) - k * _LOG10_2LO  # |r| <= 0.151
    x = r * _LN10
    return math.ldexp(_exp_reduced(x, x, 0.0), int(k))


@njit(cache=True)
def _power2(y):
    if y != y:
        return np.nan
    if y == np.inf:
        return np.inf
    if y == -np.inf:
        return 0.0
    k = math.floor(min(max(y, -1100.0), 1100.0))  # 2**floor(y) exactly, times 2**f for the fraction f
    return math.ldexp(_exp((y - k) * _LN2), int(k))


def _ufunc(function, doc: str):
    """A numpy ufunc (any shape; a scalar gives a scalar) of a compiled function of one float,
    compiled (or read from numba's cache) when first called, not on import."""
    ufunc = vectorize(cache=True)(function.py_func)
    ufunc.__doc__ = doc
    return ufunc


log = _ufunc(_log, "The natural logarithm of ``x`` (fdlibm's e_log.c).")
log10 = _ufunc(_log10, "The base-10 logarithm of ``x`` (fdlibm's e_log10.c); exactly k at the double nearest 10**k.")
log2 = _ufunc(_log2, "The base-2 logarithm of ``x``; exactly k at 2**k.")
exp = _ufunc(_exp, "e to the power ``x`` (fdlibm's e_exp.c): exp(r) times 2**k for x = k ln(2) + r.")
power10 = _ufunc(_power10, "10 to the power ``y``: 2**k times 10**r for y = k log10(2) + r; exactly the double "
                           "nearest 10**k at a whole k.")
_power_of_2 = _ufunc(_power2, "2 to the power ``y``: 2**floor(y) exactly, times 2**f for its fraction f.")


def log_base(x, base: float):
    """The logarithm of ``x`` to ``base`` (> 0, not 1)."""
    if base == 10:
        return log10(x)
    if base == 2:
        return log2(x)
    return log(x) / float(log(np.float64(base)))


def power(base: float, y):
    """``base`` (> 0) to the power ``y``."""
    if base == 10:
        return power10(y)
    if base == 2:
        return _power_of_2(y)
    return exp(np.asarray(y, dtype=np.float64) * float(log(np.float64(base))))


def geomspace(start: float, stop: float, num: int) -> np.ndarray:
    """``num`` numbers from ``start`` to ``stop`` (both > 0) evenly spaced on a log scale, as
    ``np.geomspace(start, stop, num)`` computes them (the ends exact), with :func:`log10` and
    :func:`power10`."""
    out = power10(np.linspace(float(log10(np.float64(start))), float(log10(np.float64(stop))), num))
    if num > 0:
        out[0] = start
    if num > 1:
        out[-1] = stop
    return out


def _kernel_sin(x):
    """sin(x) for |x| <= pi / 4 (fdlibm's k_sin.c)."""
    z = x * x
    w = z * z
    r = _S[1] + z * (_S[2] + z * _S[3]) + z * w * (_S[4] + z * _S[5])
    return x + (z * x) * (_S[0] + z * r)


def _kernel_cos(x):
    """cos(x) for |x| <= pi / 4 (fdlibm's k_cos.c, FreeBSD's form)."""
    z = x * x
    w = z * z
    r = z * (_C[0] + z * (_C[1] + z * _C[2])) + w * w * (_C[3] + z * (_C[4] + z * _C[5]))
    hz = 0.5 * z
    w = 1.0 - hz
    return w + (((1.0 - w) - hz) + z * r)


def cos_sin_of_turns(turns):
    """(cos, sin) of the angles ``turns`` x 360 degrees: the angle is reduced by quarter turns,
    where no rounding enters, and the rest (within 45 degrees) goes to fdlibm's kernels."""
    turns = np.asarray(turns, dtype=np.float64)
    quarters = np.rint(4.0 * turns)
    x = (turns - 0.25 * quarters) * _TWO_PI
    c, s = _kernel_cos(x), _kernel_sin(x)
    q = np.mod(quarters, 4.0)
    cos = np.where(q == 0, c, np.where(q == 1, -s, np.where(q == 2, -c, s)))
    sin = np.where(q == 0, s, np.where(q == 1, c, np.where(q == 2, -s, -c)))
    return cos + 0.0, sin + 0.0  # + 0.0 turns -0.0 into 0.0


def line_slope(x, y) -> float:
    """The least-squares slope of ``y`` on ``x`` (the first coefficient of ``np.polyfit(x, y, 1)``),
    from plain sums in a fixed order: no linear-algebra library, whose kernels sum in an order of
    their processor's."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    dx, dy = x - x.mean(), y - y.mean()
    return float((dx * dy).sum() / (dx * dx).sum())


def weighted_sum(values, weights):
    """``values @ weights`` over the last axis, as elementwise products summed by numpy's own sum
    (a fixed order on every processor), not by a linear-algebra library."""
    return (np.asarray(values, dtype=np.float64) * np.asarray(weights, dtype=np.float64)).sum(axis=-1)
