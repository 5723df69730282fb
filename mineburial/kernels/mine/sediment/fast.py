"""Fast fixed-cost rule for the sediment tractions, smooth in the state.

The default rule (``numerics.sediment_quadrature = "fast"``): the same traction law
(:func:`.laws._traction`; its semilog rate law with ``log(ratio) / ln 10`` for ``log10(ratio)``, the same up
to rounding, :func:`.laws._rate` with ``natural_log``) and the same embedded, advancing surface as
:mod:`.reference`, integrated with a fixed number of Gauss-Legendre nodes whose
positions are continuous functions of the state (``docs/notes/sediment_fast.md``).

Lateral surface, point (x, R cos t, R sin t). With phi = t - t_deep (t_deep the
direction of the deepest generator) the depth is zeta = d0 - c20 x + R rperp cos phi,
so the generators that are embedded somewhere fill |phi| < a_any and those embedded
along their whole length |phi| < a_all (closed forms: arccos of a clipped ratio). The
generators that advance somewhere fill the union of the half-circles where v.n >= 0 at
x = xa and at x = xb (v.n is linear along a generator and a pure harmonic of t at a
fixed x). The outer integral runs over the intersection of the two arcs, in panels
between breakpoints that are continuous functions of the state, clamped into it:

* +-a_all (the seabed line reaches a body end);
* the four angles where the delta line v.n = 0 crosses a body end (for a translation
  they coincide pairwise and the panels end exactly at the jump of the integrand);
* with friction, the angles where the circumferential slip v_t reverses at a body end
  (two per end); a root that does not exist is replaced by the clipped double root
  (where it is born), so the breakpoints never jump;
* the angles where the seabed line and the delta line cross inside the lateral surface
  (issue 34: an embedded, advancing sliver between the two lines, as a rotating slap cuts,
  ends there; without them its few nodes fell mostly where the generators are empty):
  the arguments of the four roots of a self-inversive quartic, a complex pair giving its
  clipped double root, so these never jump either (:func:`_crossing_angles`);
* phi = +-pi/2, so that no panel is wider than a quarter of the circle.

Each panel carries N_T Gauss nodes; a panel of zero length contributes nothing, so
breakpoints crossing each other or the ends change the result continuously. A sliver panel
(narrower than PANEL_SKIP of the embedded half-arc: breakpoints that coincide to rounding, as
they do for a drop that moves in one vertical plane) carries none, with a linear weight ramp up
to twice that width so that the force stays continuous (issue 34 item 4); the caps' u-panels
the same. At each
node the embedded and advancing x-interval of the generator is exact (both conditions
are linear in x), with N_XR = 2 Gauss nodes whose weights are product weights for the
advancing switch's ramp along the generator (:func:`_ramp_weights`: exact for the ramp
times a linear function, where an interval ends at the delta line; issue 34 item 4).

End caps, point (xc, s d + t e) with d the unit direction of increasing depth in the
cap plane: zeta = e0 + rperp s > 0 is s > s0, and s = R sin u, t in
[-R cos u, R cos u] (area element R cos u du dt, smooth up to the rim). The outer
variable u runs over [asin(clip(s0/R)), pi/2], split where the delta chord meets the
rim (clipped double roots when it does not), N_U nodes a panel; the inner t-interval
is cut exactly by the delta chord, N_S nodes.

Fixed node counts, no state-dependent refinement, no allocation.
"""

import math

from mineburial._numba import kernel, small_kernel
from mineburial.kernels.mine.sediment.laws import GL_NODES as _GL_NODES
from mineburial.kernels.mine.sediment.laws import GL_WEIGHTS as _GL_WEIGHTS
from mineburial.kernels.mine.sediment.laws import (
    LAW_MU,
    LAW_ROW,
    LAW_VREG_N,
    _depth_terms,
    _linear_depth_terms,
    _traction_at,
    add_point_traction,
    add_weighted,
)

#: Gauss-Legendre points: per theta panel (N_T), per generator (N_X), per u panel of a
#: cap (N_U), per cap chord (N_S) (the depth is constant along a chord).
N_T = 3
N_X = 3
N_U = 4
N_S = 2
#: Nodes per generator of the cylinder's lateral surface (issue 34 item 4): 2 Gauss nodes with
#: product weights for the advancing switch's ramp (:func:`_ramp_weights`); ``N_X`` (3 plain Gauss
#: nodes) stays the rule of the bodies of revolution.
N_XR = 2
#: Where v.n changes along a generator's interval by less than this fraction of
#: sqrt(v.n^2 + switch_speed^2) at its middle (from the middle to an end), the ramp's first moment
#: comes from its Taylor series (truncation ~ RAMP_SERIES^5), where the closed form loses digits by
#: cancellation (~ 1e-16 / RAMP_SERIES^2).
RAMP_SERIES = 1.0e-2
#: Durand-Kerner sweeps for the seabed/delta crossing angles (at most), and the relative size of
#: the quartic's leading coefficient below which it counts as degenerate.
CROSS_ITERATIONS = 32
CROSS_DEGENERATE = 1.0e-9
#: The sweeps stop once no root moved by more than this fraction of its modulus (squared here):
#: the iteration converges quadratically at simple roots, so the roots are then at rounding level
#: (issue 34: 6-7 sweeps on the default ensemble's contact states, at most 11 in 2,000, where
#: there were always 16; the cap, 16 before, is 32 so that the rare start that converges slowly
#: converges too, and a double root, the birth of a pair, where it converges linearly, is
#: followed further).
CROSS_TOL2 = 1.0e-20
#: A lateral panel narrower than this fraction of the embedded half-arc ``a_any`` carries no nodes, one
#: twice as wide carries them at full weight, and its nodes' weights grow linearly in between
#: (issue 34 item 4). Half the panels of the default ensemble's contact states are such slivers
#: (widths 1e-16-1e-6 rad: breakpoints that coincide up to rounding, or nearly, for a drop that moves
#: almost in one vertical plane: the delta-line and slip-reversal angles at the two ends and the
#: quarter points), and their nodes were half the tractions of a call. What they carried is at most
#: ``2 PANEL_SKIP`` of the arc's force (relative to the force scale, times the ratio of the
#: largest to the mean line integral); the ramp keeps the force continuous in the state.
#: The end caps' u-panels the same, as a fraction of the embedded u-range (a tenth of the u-panels,
#: 15 % of the caps' tractions). ``_lateral``, ``_cap`` take it by default (so do the bodies of
#: revolution's cylindrical segments and caps); with ``skip=0.0`` they are the rule without it (every
#: panel, :func:`fast_tractions_every_panel`).
PANEL_SKIP = 1.0e-6


_PI = math.pi
_TWO_PI = 2.0 * math.pi
_HALF_PI = 0.5 * math.pi


@small_kernel
def _clip1(r):
    """r clipped to [-1, 1] (NaN -> 1)."""
    if r > 1.0:
        return 1.0
    if r < -1.0:
        return -1.0
    if not (r == r):
        return 1.0
    return r


@small_kernel
def _local(t, t0, amax):
    """Angle t as an offset from t0 in [-pi, pi], clamped to [-amax, amax]."""
    p = t - t0
    p -= _TWO_PI * math.floor(p / _TWO_PI + 0.5)
    if p > amax:
        return amax
    if p < -amax:
        return -amax
    return p


@small_kernel
def _harmonic_roots(k, a, b):
    """Roots of k + a cos t + b sin t = 0 as (psi - w, psi + w), psi = atan2(b, a),
    w = arccos(clip(-k / amp)): when there is no root, the double root where the
    roots are born (continuous in (k, a, b) wherever amp > 0)."""
    amp = math.sqrt(a * a + b * b)
    psi = math.atan2(b, a)
    if amp > 0.0:
        w = math.acos(_clip1(-k / amp))
    else:
        w = 0.0
    return psi - w, psi + w


@small_kernel
def _nonzero(a, b):
    """``math.hypot(a, b) > 0.0`` for every a, b (infinities and NaN too) without computing hypot."""
    return abs(a) + abs(b) > 0.0 or abs(a) == math.inf or abs(b) == math.inf


@small_kernel
def _zero_roots(a, b):
    """:func:`_harmonic_roots` with k = 0 (the delta line at a body end): there w = arccos(-0.0)
    = pi/2 exactly, so no arccos (issue 34 item 4; the same values to the bit)."""
    psi = math.atan2(b, a)
    if math.sqrt(a * a + b * b) > 0.0:
        return psi - _HALF_PI, psi + _HALF_PI
    return psi, psi


@small_kernel
def _on_body(w, tdeep, a_any, R, xa, xb, d0, c20, c21, c22, rp):
    """Crossing angle t = arg w (w a root of :func:`_crossing_roots`; cos t, sin t = w / |w|) of the
    seabed and delta lines as a breakpoint (offset from tdeep, clamped like the others): where the
    crossing lies beyond a body end, the angle where the seabed line reaches that end instead (on the
    same side of tdeep), which it equals when the crossing passes the end; so a crossing outside the
    body adds no panel and none jumps."""
    p = _local(math.atan2(w.imag, w.real), tdeep, a_any)
    if c20 == 0.0 or not (rp > 0.0):
        return p
    aw = math.sqrt(w.real * w.real + w.imag * w.imag)  # cos t, sin t = w / |w|, no trigonometric call
    xc = (d0 - R * (c21 * (w.real / aw) + c22 * (w.imag / aw))) / c20  # the seabed line's x at t
    if xc > xb:
        xe = xb
    elif xc < xa:
        xe = xa
    else:
        return p
    a_end = math.acos(_clip1(-(d0 - c20 * xe) / rp))
    return min(a_end, a_any) if p >= 0.0 else -min(a_end, a_any)


@small_kernel
def _next_break(bps, cur, end):
    """Smallest breakpoint above cur, at most end."""
    nxt = end
    for k in range(len(bps)):
        b = bps[k]
        if b > cur and b < nxt:
            nxt = b
    return nxt


@small_kernel
def _cs(a, b):
    """(min, max) of two numbers, neither NaN."""
    if b < a:
        return b, a
    return a, b


@small_kernel
def _number(b, fill):
    """b, or ``fill`` where b is NaN."""
    return b if b == b else fill


@small_kernel
def _sorted16(bps, fill):
    """The 16 breakpoints of :func:`_lateral` in increasing order, NaN replaced by ``fill`` (a value
    that no panel ends at): Batcher's odd-even merge network, 63 compare-exchanges, no allocation.
    The panel walk then reads each once (issue 34 item 4: :func:`_next_break`, a scan of all 16 a
    panel, was 7 % of the rule's instructions)."""
    b0, b1, b2, b3, b4, b5, b6, b7, b8, b9, b10, b11, b12, b13, b14, b15 = bps
    b0 = _number(b0, fill)
    b1 = _number(b1, fill)
    b2 = _number(b2, fill)
    b3 = _number(b3, fill)
    b4 = _number(b4, fill)
    b5 = _number(b5, fill)
    b6 = _number(b6, fill)
    b7 = _number(b7, fill)
    b8 = _number(b8, fill)
    b9 = _number(b9, fill)
    b10 = _number(b10, fill)
    b11 = _number(b11, fill)
    b12 = _number(b12, fill)
    b13 = _number(b13, fill)
    b14 = _number(b14, fill)
    b15 = _number(b15, fill)
    b0, b1 = _cs(b0, b1)
    b2, b3 = _cs(b2, b3)
    b0, b2 = _cs(b0, b2)
    b1, b3 = _cs(b1, b3)
    b1, b2 = _cs(b1, b2)
    b4, b5 = _cs(b4, b5)
    b6, b7 = _cs(b6, b7)
    b4, b6 = _cs(b4, b6)
    b5, b7 = _cs(b5, b7)
    b5, b6 = _cs(b5, b6)
    b0, b4 = _cs(b0, b4)
    b2, b6 = _cs(b2, b6)
    b2, b4 = _cs(b2, b4)
    b1, b5 = _cs(b1, b5)
    b3, b7 = _cs(b3, b7)
    b3, b5 = _cs(b3, b5)
    b1, b2 = _cs(b1, b2)
    b3, b4 = _cs(b3, b4)
    b5, b6 = _cs(b5, b6)
    b8, b9 = _cs(b8, b9)
    b10, b11 = _cs(b10, b11)
    b8, b10 = _cs(b8, b10)
    b9, b11 = _cs(b9, b11)
    b9, b10 = _cs(b9, b10)
    b12, b13 = _cs(b12, b13)
    b14, b15 = _cs(b14, b15)
    b12, b14 = _cs(b12, b14)
    b13, b15 = _cs(b13, b15)
    b13, b14 = _cs(b13, b14)
    b8, b12 = _cs(b8, b12)
    b10, b14 = _cs(b10, b14)
    b10, b12 = _cs(b10, b12)
    b9, b13 = _cs(b9, b13)
    b11, b15 = _cs(b11, b15)
    b11, b13 = _cs(b11, b13)
    b9, b10 = _cs(b9, b10)
    b11, b12 = _cs(b11, b12)
    b13, b14 = _cs(b13, b14)
    b0, b8 = _cs(b0, b8)
    b4, b12 = _cs(b4, b12)
    b4, b8 = _cs(b4, b8)
    b2, b10 = _cs(b2, b10)
    b6, b14 = _cs(b6, b14)
    b6, b10 = _cs(b6, b10)
    b2, b4 = _cs(b2, b4)
    b6, b8 = _cs(b6, b8)
    b10, b12 = _cs(b10, b12)
    b1, b9 = _cs(b1, b9)
    b5, b13 = _cs(b5, b13)
    b5, b9 = _cs(b5, b9)
    b3, b11 = _cs(b3, b11)
    b7, b15 = _cs(b7, b15)
    b7, b11 = _cs(b7, b11)
    b3, b5 = _cs(b3, b5)
    b7, b9 = _cs(b7, b9)
    b11, b13 = _cs(b11, b13)
    b1, b2 = _cs(b1, b2)
    b3, b4 = _cs(b3, b4)
    b5, b6 = _cs(b5, b6)
    b7, b8 = _cs(b7, b8)
    b9, b10 = _cs(b9, b10)
    b11, b12 = _cs(b11, b12)
    b13, b14 = _cs(b13, b14)
    return b0, b1, b2, b3, b4, b5, b6, b7, b8, b9, b10, b11, b12, b13, b14, b15


@kernel
def _quartic_roots(c0, ca1, cb1, ca2, cb2):
    """The four roots w = |w| exp(i t) whose arguments t are the zeros of the degree-2 trigonometric
    polynomial ``c0 + ca1 cos t + cb1 sin t + ca2 cos 2t + cb2 sin 2t``: the roots of the quartic w^2
    p(t) in w = exp(i t) (a self-inversive polynomial: its roots lie on the unit circle, where they are
    real zeros, or in pairs w, 1/conj(w) with one argument, the clipped double zero where a pair of real
    zeros is born). Durand-Kerner sweeps (:func:`_dk_sweeps`) from the closed form's roots
    (:func:`_quartic_starts`, Ferrari's; issue 34 item 4: one sweep on each of 5,076 sampled contact
    states of the default ensemble, where the fixed starts took 5-16) until a sweep moves none by more
    than 1e-10 of its modulus (CROSS_TOL2; at most CROSS_ITERATIONS): a continuous function of the
    coefficients up to rounding (at simple roots the error after that sweep is of the order of the
    square of that move; the roots the sweeps converge to do not depend on the starts but at rounding
    level, or at ~1e-16 / (the roots' separation) near a double root, where any method is as
    ill-conditioned). NaN (all four) when the quartic degenerates (its leading coefficient below
    CROSS_DEGENERATE of the largest). Shared by the cylinder (:func:`_crossing_roots`,
    :func:`_crossing_angles`) and the tapered generators of the bodies of revolution
    (:func:`mineburial.kernels.mine.bodies.revolution_sediment._trig2_angles`). A compile unit of its own
    (``kernel``): inlined into each caller, the closed form and the sweeps added ~7 s of CPU to the default
    path's cold compile (``benchmarks/compare_compile.py``, 49.6 -> 56.7 s median); compiled once, 3-6 s of
    that is saved (issue 34 item 1), for a call a lateral call."""
    lead = complex(0.5 * ca2, -0.5 * cb2)
    big = max(abs(c0), max(math.hypot(ca1, cb1), math.hypot(ca2, cb2)))
    if not (abs(lead) > CROSS_DEGENERATE * big):
        nan = complex(math.nan, math.nan)
        return nan, nan, nan, nan
    # in real arithmetic: the operations of numba's (CPython's) complex product and quotient, in
    # their order, without their per-quotient exception path (issue 34 item 4)
    lr = 0.5 * ca2
    li = -0.5 * cb2
    q3r, q3i = _cdiv(0.5 * ca1, -0.5 * cb1, lr, li)
    q2r, q2i = _cdiv(c0, 0.0, lr, li)
    q1r, q1i = _cdiv(0.5 * ca1, 0.5 * cb1, lr, li)
    q0r, q0i = _cdiv(0.5 * ca2, 0.5 * cb2, lr, li)
    q = (q3r, q3i, q2r, q2i, q1r, q1i, q0r, q0i)
    # the sweeps start at the closed form's roots (:func:`_quartic_starts`), so that one or two
    # sweeps polish them (issue 34 item 4); where that fails (a NaN: two starts that coincide
    # exactly, an overflow), from the fixed starts (0.4 + 0.9i)^k as before
    # (one call site of the inlined sweeps, so that they are compiled once: issue 34 item 1)
    starts = _quartic_starts(c0, ca1, cb1, ca2, cb2)
    for _attempt in range(2):
        r0r, r0i, r1r, r1i, r2r, r2i, r3r, r3i = _dk_sweeps(starts, q)
        if r0r + r0i + r1r + r1i + r2r + r2i + r3r + r3i == r0r + r0i + r1r + r1i + r2r + r2i + r3r + r3i:
            break
        f2r, f2i = _cmul(0.4, 0.9, 0.4, 0.9)
        f3r, f3i = _cmul(f2r, f2i, 0.4, 0.9)
        starts = (1.0, 0.0, 0.4, 0.9, f2r, f2i, f3r, f3i)
    return complex(r0r, r0i), complex(r1r, r1i), complex(r2r, r2i), complex(r3r, r3i)


@small_kernel
def _dk_sweeps(starts, q):
    """Durand-Kerner sweeps of the monic quartic ``q`` (:func:`_dk_step`) from ``starts`` (four roots
    as real, imaginary pairs) until a sweep moves none by more than 1e-10 of its modulus
    (CROSS_TOL2), at most CROSS_ITERATIONS; a NaN ends them (the roots are then NaN)."""
    r0r, r0i, r1r, r1i, r2r, r2i, r3r, r3i = starts
    for _ in range(CROSS_ITERATIONS):
        d0r, d0i = _dk_step(r0r, r0i, r1r, r1i, r2r, r2i, r3r, r3i, q)
        r0r = r0r - d0r
        r0i = r0i - d0i
        d1r, d1i = _dk_step(r1r, r1i, r0r, r0i, r2r, r2i, r3r, r3i, q)
        r1r = r1r - d1r
        r1i = r1i - d1i
        d2r, d2i = _dk_step(r2r, r2i, r0r, r0i, r1r, r1i, r3r, r3i, q)
        r2r = r2r - d2r
        r2i = r2i - d2i
        d3r, d3i = _dk_step(r3r, r3i, r0r, r0i, r1r, r1i, r2r, r2i, q)
        r3r = r3r - d3r
        r3i = r3i - d3i
        m0 = d0r * d0r + d0i * d0i
        m1 = d1r * d1r + d1i * d1i
        m2 = d2r * d2r + d2i * d2i
        m3 = d3r * d3r + d3i * d3i
        if (
            m0 <= CROSS_TOL2 * (r0r * r0r + r0i * r0i)
            and m1 <= CROSS_TOL2 * (r1r * r1r + r1i * r1i)
            and m2 <= CROSS_TOL2 * (r2r * r2r + r2i * r2i)
            and m3 <= CROSS_TOL2 * (r3r * r3r + r3i * r3i)
        ):
            break
        if not (m0 + m1 + m2 + m3 == m0 + m1 + m2 + m3):  # NaN (or infinite): give up
            nan = math.nan
            return nan, nan, nan, nan, nan, nan, nan, nan
    return r0r, r0i, r1r, r1i, r2r, r2i, r3r, r3i


@small_kernel
def _quartic_starts(c0, ca1, cb1, ca2, cb2):
    """Approximations of the four roots of :func:`_quartic_roots`'s quartic (real, imaginary pairs), by
    Ferrari's closed form for the real quartic in x = tan(s / 2), t = t0 + s: ``(1 + x^2)^2 p(t0 + s)``.
    t0 is the one of the 8 angles k pi / 4 + pi where |p| is largest (the point x = infinity, t = t0 +
    pi, is then no root, and the quartic's leading coefficient p(t0 + pi) at least ~ the coefficients'
    size). A real root x gives w = exp(i t0) (1 + i x) / (1 - i x) on the unit circle, a complex pair
    x = al +- i be the pair w, 1 / conj(w) with one argument. Not exact (the resolvent cubic and the
    quadratic factors lose digits near multiple roots): only starts for :func:`_dk_sweeps`."""
    h = 0.7071067811865476  # sqrt(2) / 2 = cos(pi / 4)
    # |p| at phi = k pi / 4; cos, sin of phi and of 2 phi where it is largest
    best = abs(c0 + ca1 + ca2)
    cf, sf, c2f, s2f = 1.0, 0.0, 1.0, 0.0
    v = abs(c0 + h * (ca1 + cb1) + cb2)
    if v > best:
        best, cf, sf, c2f, s2f = v, h, h, 0.0, 1.0
    v = abs(c0 + cb1 - ca2)
    if v > best:
        best, cf, sf, c2f, s2f = v, 0.0, 1.0, -1.0, 0.0
    v = abs(c0 + h * (cb1 - ca1) - cb2)
    if v > best:
        best, cf, sf, c2f, s2f = v, -h, h, 0.0, -1.0
    v = abs(c0 - ca1 + ca2)
    if v > best:
        best, cf, sf, c2f, s2f = v, -1.0, 0.0, 1.0, 0.0
    v = abs(c0 - h * (ca1 + cb1) + cb2)
    if v > best:
        best, cf, sf, c2f, s2f = v, -h, -h, 0.0, 1.0
    v = abs(c0 - cb1 - ca2)
    if v > best:
        best, cf, sf, c2f, s2f = v, 0.0, -1.0, -1.0, 0.0
    v = abs(c0 + h * (ca1 - cb1) - cb2)
    if v > best:
        best, cf, sf, c2f, s2f = v, h, -h, 0.0, -1.0
    # p(t0 + s) = c0 + a1 cos s + b1 sin s + a2 cos 2s + b2 sin 2s, t0 = phi + pi
    a1 = -(ca1 * cf + cb1 * sf)
    b1 = -(cb1 * cf - ca1 * sf)
    a2 = ca2 * c2f + cb2 * s2f
    b2 = cb2 * c2f - ca2 * s2f
    # (1 + x^2)^2 p = e4 x^4 + e3 x^3 + e2 x^2 + e1 x + e0, made monic, then depressed (x = y - a / 4)
    e4 = c0 - a1 + a2  # = p(phi), the largest of the 8
    a = (2.0 * b1 - 4.0 * b2) / e4
    b = (2.0 * c0 - 6.0 * a2) / e4
    c = (2.0 * b1 + 4.0 * b2) / e4
    d = (c0 + a1 + a2) / e4
    aa = a * a
    p = b - 0.375 * aa
    qq = c - 0.5 * a * b + 0.125 * aa * a
    r = d - 0.25 * a * c + 0.0625 * aa * b - 0.01171875 * aa * aa
    # y^4 + p y^2 + qq y + r = (y^2 + m)^2 - (s y - tq)^2 with 2m - p = s^2, m^2 - r = tq^2: m the
    # largest real root of the resolvent cubic m^3 - p/2 m^2 - r m + p r / 2 - qq^2 / 8 (>= p / 2)
    k2 = -0.5 * p
    pc = -r - k2 * k2 / 3.0
    qc = 2.0 * k2 * k2 * k2 / 27.0 + k2 * r / 3.0 + 0.5 * p * r - 0.125 * qq * qq
    disc = 0.25 * qc * qc + pc * pc * pc / 27.0
    if disc > 0.0:
        u = -0.5 * qc - math.copysign(math.sqrt(disc), qc)
        u = math.copysign(abs(u) ** (1.0 / 3.0), u)
        z = u - pc / (3.0 * u)
    elif pc < 0.0:
        rt = math.sqrt(-pc / 3.0)
        z = 2.0 * rt * math.cos(math.acos(_clip1(-0.5 * qc / (rt * rt * rt))) / 3.0)
    else:
        z = 0.0
    m = z - k2 / 3.0
    # s tq = qq / 2: the larger of s^2, |tq| from m, the other from that product (where qq ~ 0, as for
    # a drop in one vertical plane, 2m - p cancels to ~eps, and its square root would be ~1e-8)
    s2 = max(2.0 * m - p, 0.0)
    t2 = max(m * m - r, 0.0)
    if s2 * s2 >= t2 and s2 > 0.0:
        s = math.sqrt(s2)
        tq = 0.5 * qq / s
    elif t2 > 0.0:
        tq = math.copysign(math.sqrt(t2), qq)
        s = 0.5 * qq / tq
    else:
        s = 0.0
        tq = 0.0
    # the two quadratic factors y^2 + s y + m - tq and y^2 - s y + m + tq
    xs = -0.25 * a
    x0r, x0i, x1r, x1i = _quadratic_roots(s, m - tq, xs)
    x2r, x2i, x3r, x3i = _quadratic_roots(-s, m + tq, xs)
    w0r, w0i = _tan_half_root(x0r, x0i, cf, sf)
    w1r, w1i = _tan_half_root(x1r, x1i, cf, sf)
    w2r, w2i = _tan_half_root(x2r, x2i, cf, sf)
    w3r, w3i = _tan_half_root(x3r, x3i, cf, sf)
    return w0r, w0i, w1r, w1i, w2r, w2i, w3r, w3i


@small_kernel
def _quadratic_roots(bq, cq, xs):
    """The two roots x = xs + y of y^2 + bq y + cq (real, imaginary pairs; a complex pair with the
    positive imaginary part first)."""
    dq = 0.25 * bq * bq - cq
    mid = xs - 0.5 * bq
    if dq >= 0.0:
        e = math.sqrt(dq)
        return mid - e, 0.0, mid + e, 0.0
    e = math.sqrt(-dq)
    return mid, e, mid, -e


@small_kernel
def _tan_half_root(xr, xi, cf, sf):
    """w = exp(i t0) (1 + i x) / (1 - i x) for x = xr + i xi, exp(i t0) = -(cf + i sf): t0 + 2 atan(x)
    for real x; a pair x, conj(x) gives w, 1 / conj(w), of one argument."""
    nr = 1.0 - xr * xr - xi * xi
    ni = 2.0 * xr
    den = (1.0 + xi) * (1.0 + xi) + xr * xr
    return (ni * sf - nr * cf) / den, -(nr * sf + ni * cf) / den


@small_kernel
def _cmul(ar, ai, br, bi):
    """(ar + i ai)(br + i bi) by the operations of numba's complex product (CPython's
    ``_Py_c_prod``, without the infinities' recovery of Python >= 3.14, which numba adds only there)."""
    return ar * br - ai * bi, ar * bi + ai * br


@small_kernel
def _cdiv(ar, ai, br, bi):
    """(ar + i ai) / (br + i bi) by the operations of numba's complex quotient (CPython's
    ``_Py_c_quot``: Smith's scaling); a zero divisor gives NaN (numba's would raise)."""
    abr = abs(br)
    abi = abs(bi)
    if abr >= abi:
        ratio = bi / br
        denom = br + bi * ratio
        return (ar + ai * ratio) / denom, (ai - ar * ratio) / denom
    if abi >= abr:
        ratio = br / bi
        denom = br * ratio + bi
        return (ar * ratio + ai) / denom, (ai * ratio - ar) / denom
    return math.nan, math.nan


@small_kernel
def _dk_step(rr, ri, ar, ai, br, bi, cr, ci, q):
    """Durand-Kerner correction p(r) / ((r - a)(r - b)(r - c)) of the monic quartic
    p(r) = (((r + q3) r + q2) r + q1) r + q0, ``q`` = (q3, q2, q1, q0) as (real, imag) pairs,
    by the complex operations of the sweep in that order."""
    q3r, q3i, q2r, q2i, q1r, q1i, q0r, q0i = q
    pr, pi = _cmul(rr + q3r, ri + q3i, rr, ri)
    pr, pi = _cmul(pr + q2r, pi + q2i, rr, ri)
    pr, pi = _cmul(pr + q1r, pi + q1i, rr, ri)
    pr = pr + q0r
    pi = pi + q0i
    dr, di = _cmul(rr - ar, ri - ai, rr - br, ri - bi)
    dr, di = _cmul(dr, di, rr - cr, ri - ci)
    return _cdiv(pr, pi, dr, di)


@small_kernel
def _quartic_angles(c0, ca1, cb1, ca2, cb2):
    """The arguments of :func:`_quartic_roots` (NaN when the quartic degenerates)."""
    return _arguments(_quartic_roots(c0, ca1, cb1, ca2, cb2))


@small_kernel
def _arguments(roots):
    """The arguments of four complex numbers (NaN for NaN)."""
    r0, r1, r2, r3 = roots
    return (
        math.atan2(r0.imag, r0.real),
        math.atan2(r1.imag, r1.real),
        math.atan2(r2.imag, r2.real),
        math.atan2(r3.imag, r3.real),
    )


@small_kernel
def _crossing_roots(a0, ac, as_, a1, bc, bs, k1c, k1s):
    """:func:`_crossing_angles` as the roots w whose arguments they are (cos t + i sin t = w / |w|)."""
    return _quartic_roots(
        0.5 * (ac * bc + as_ * bs),
        a0 * bc - a1 * k1c,
        a0 * bs - a1 * k1s,
        0.5 * (ac * bc - as_ * bs),
        0.5 * (ac * bs + as_ * bc),
    )


@small_kernel
def _crossing_angles(a0, ac, as_, a1, bc, bs, k1c, k1s):
    """Angles where the seabed line and the delta line cross (anywhere along x): the zeros of
    the degree-2 trigonometric polynomial (a0 + ac cos t + as sin t)(bc cos t + bs sin t)
    - a1 (k1c cos t + k1s sin t) = 0, the arguments of :func:`_crossing_roots`. When the quartic degenerates
    (no rotation across the axis: the delta line is then made of generators, whose angles are
    breakpoints already), the four angles are NaN."""
    return _arguments(_crossing_roots(a0, ac, as_, a1, bc, bs, k1c, k1s))


@small_kernel
def _ramp_weights(vm, dv, vrn):
    """Weights (per unit half-length) of the 2 Gauss nodes of a generator's interval that make
    the rule exact for h(x) p(x), p any linear function and h = v.n / sqrt(v.n^2 + vrn^2) the
    advancing switch's ramp (:func:`.laws._traction`), v.n = vm + dv tau on tau in [-1, 1]
    (product integration; issue 34 item 4). The tractions are such products (plus the
    friction, which has no ramp); plain Gauss nodes need 3 a generator for the ramp where the
    interval ends at the delta line. Each node's traction already holds h at the node, so the
    weight returned is the product weight over h there (0 where h is 0: no traction there).

    Moments over tau: M0 = int h, M1 = int tau h, in u = v.n / vrn (u = um + du tau):
    int h = [sqrt(1 + u^2)] / du and int (u - um) h = [(u S - asinh u) / 2 - um S] / du;
    M0 in its cancellation-free form, M1 from its Taylor series where |du| < RAMP_SERIES S(um)."""
    g = _GL_NODES[N_XR, 1]  # the nodes are -g, g
    if not (vrn > 0.0):
        return _GL_WEIGHTS[N_XR, 0], _GL_WEIGHTS[N_XR, 1]
    um = vm / vrn
    du = dv / vrn
    ulo = um - du
    uhi = um + du
    slo = math.sqrt(1.0 + ulo * ulo)
    shi = math.sqrt(1.0 + uhi * uhi)
    sm = math.sqrt(1.0 + um * um)
    m0 = 2.0 * (uhi + ulo) / (shi + slo)
    if abs(du) < RAMP_SERIES * sm:
        # h(u) = hm + h1 (du tau) + h3 (du tau)^3 / 6 + ..., h1 = S^-3, h3 = 3 (4 u^2 - 1) / S^7
        m1 = du * (2.0 / 3.0) / (sm * sm * sm) + du * du * du * 0.2 * (4.0 * um * um - 1.0) / sm**7
    else:
        # asinh(uhi) - asinh(ulo) = asinh(uhi slo - ulo shi) (the sinh of a difference), the argument
        # without cancellation: where uhi, ulo share a sign, (uhi - ulo)(uhi + ulo) / (uhi slo + ulo shi)
        if uhi * ulo > 0.0:
            arg = (uhi - ulo) * (uhi + ulo) / (uhi * slo + ulo * shi)
        else:
            arg = uhi * slo - ulo * shi
        m1 = (0.5 * (uhi * shi - ulo * slo - math.asinh(arg)) - um * (shi - slo)) / (du * du)
    # product weights at -g, g: wa + wb = m0, g (wb - wa) = m1
    wa = 0.5 * (m0 - m1 / g)
    wb = 0.5 * (m0 + m1 / g)
    ha = vm - dv * g
    hb = vm + dv * g
    ha = ha / math.sqrt(ha * ha + vrn * vrn) if ha > 0.0 else 0.0
    hb = hb / math.sqrt(hb * hb + vrn * vrn) if hb > 0.0 else 0.0
    # where v.n is 0 at a node (v.n = 0 along the whole generator, up to rounding: the nodes are
    # inside the interval where v.n >= 0) only the friction acts there: the weight is the limit
    # of the ratio as v.n -> 0 along the generator, Gauss's
    return (wa / ha if ha > 0.0 else 1.0), (wb / hb if hb > 0.0 else 1.0)


@small_kernel
def _paired_node(k, a, cm, sm, ca, sa):
    """Cosine and sine of node k of a panel whose Gauss nodes come in pairs mid -+ a (k even: mid - a, which
    computes cos a, sin a; k odd: mid + a, from the (ca, sa) of the even node before it), by the addition
    theorem from the middle's (cm, sm): two trigonometric calls a pair (issue 34 item 4; the lateral
    panels and the caps' u-panels). Returns (cos, sin, ca, sa) to carry to the odd node."""
    if k % 2 == 0:
        ca = math.cos(a)
        sa = math.sin(a)
        return cm * ca + sm * sa, sm * ca - cm * sa, ca, sa
    return cm * ca - sm * sa, sm * ca + cm * sa, ca, sa


@small_kernel
def _generator_span(c, s, R, xa, xb, d0, c20, c21, c22, vbody, law):
    """The embedded, advancing x-interval of the generator at angle (c, s), as (ok, h, mid, a0, a1, wa, wb):
    ok False where it is empty; its half-length h and middle mid; the seabed's zeta = a0 + a1 x; the
    ramp's product weights of its N_XR nodes (:func:`_ramp_weights`). ``_lateral`` sums the tractions at
    the nodes itself: the generator's kernel that did (and took the bank) made numba count the bank's
    reference up and down at every generator (issue 34 item 4: -0.9 % instructions a drop)."""
    v1, v2, v3, w1, w2, w3 = vbody
    y = R * c
    z = R * s
    lo = xa
    hi = xb
    # seabed: zeta = a0 + a1 x > 0
    a0 = d0 - c21 * y - c22 * z
    a1 = -c20
    if a1 > 0.0:
        lo = max(lo, -a0 / a1)
    elif a1 < 0.0:
        hi = min(hi, -a0 / a1)
    elif not (a0 > 0.0):
        return False, 0.0, 0.0, a0, a1, 0.0, 0.0
    # advancing: v.n = b0 + b1 x >= 0
    b0 = v2 * c + v3 * s
    b1 = w3 * c - w2 * s
    if b1 > 0.0:
        lo = max(lo, -b0 / b1)
    elif b1 < 0.0:
        hi = min(hi, -b0 / b1)
    elif b0 < 0.0:
        return False, 0.0, 0.0, a0, a1, 0.0, 0.0
    if not (hi > lo):
        return False, 0.0, 0.0, a0, a1, 0.0, 0.0
    h = 0.5 * (hi - lo)
    mid = 0.5 * (hi + lo)
    wa, wb = _ramp_weights(b0 + b1 * mid, b1 * h, law[LAW_VREG_N])
    return True, h, mid, a0, a1, wa, wb


@kernel
def _lateral(R, xa, xb, d0, c20, c21, c22, vbody, law, bank, tangential, skip=PANEL_SKIP):
    """Moments over the lateral surface; ``skip`` the sliver panels' threshold (default
    :data:`PANEL_SKIP`; 0: every panel carries its nodes)."""
    v1, v2, v3, w1, w2, w3 = vbody
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    rp = R * math.sqrt(c21 * c21 + c22 * c22)
    zhi = d0 - min(c20 * xa, c20 * xb)  # depth of the axis at its deeper end
    zlo = d0 - max(c20 * xa, c20 * xb)  # ... at its shallower end
    # zeta = (d0 - c20 x) + rp cos(phi), phi = t - tdeep
    if rp > 0.0:
        a_any = math.acos(_clip1(-zhi / rp))
        a_all = math.acos(_clip1(-zlo / rp))
        tdeep = math.atan2(-c22, -c21)
    else:
        a_any = _PI if zhi > 0.0 else 0.0
        a_all = _PI if zlo > 0.0 else 0.0
        tdeep = 0.0
    if not (a_any > 0.0):
        return f1, f2, f3, m1, m2, m3
    # breakpoints (offsets from tdeep, clamped to [-a_any, a_any]): the seabed line
    # reaching a body end, the delta line crossing a body end (v.n at x = xa, xb is a pure
    # harmonic of t) and, with friction, the reversal of the circumferential slip
    # v_t = w1 R + (v3 - w2 x) cos t - (v2 + w3 x) sin t at a body end
    pa0, pa1 = _zero_roots(v2 + w3 * xa, v3 - w2 * xa)
    pb0, pb1 = _zero_roots(v2 + w3 * xb, v3 - w2 * xb)
    q0 = a_any
    q1 = a_any
    q2 = a_any
    q3 = a_any
    if tangential:
        r0, r1 = _harmonic_roots(w1 * R, v3 - w2 * xa, -(v2 + w3 * xa))
        r2, r3 = _harmonic_roots(w1 * R, v3 - w2 * xb, -(v2 + w3 * xb))
        q0 = _local(r0, tdeep, a_any)
        q1 = _local(r1, tdeep, a_any)
        q2 = _local(r2, tdeep, a_any)
        q3 = _local(r3, tdeep, a_any)
    # where the seabed line and the delta line cross inside the lateral surface: zeta = 0 and
    # v.n = 0 on one generator, a0(t) b1(t) - a1 b0(t) = 0 (an embedded, advancing sliver
    # between the two lines ends there)
    r0c, r1c, r2c, r3c = _crossing_roots(d0, -R * c21, -R * c22, -c20, w3, -w2, v2, v3)
    if r0c.real == r0c.real:
        x0 = _on_body(r0c, tdeep, a_any, R, xa, xb, d0, c20, c21, c22, rp)
        x1 = _on_body(r1c, tdeep, a_any, R, xa, xb, d0, c20, c21, c22, rp)
        x2 = _on_body(r2c, tdeep, a_any, R, xa, xb, d0, c20, c21, c22, rp)
        x3 = _on_body(r3c, tdeep, a_any, R, xa, xb, d0, c20, c21, c22, rp)
    else:  # none: at the domain's end, where a breakpoint changes nothing
        x0 = a_any
        x1 = a_any
        x2 = a_any
        x3 = a_any
    # and, so that no panel is wider than pi/2, the quarter points of the circle
    hq = min(_HALF_PI, a_any)
    bps = (
        x0,
        x1,
        x2,
        x3,
        -a_all,
        a_all,
        _local(pa0, tdeep, a_any),
        _local(pa1, tdeep, a_any),
        _local(pb0, tdeep, a_any),
        _local(pb1, tdeep, a_any),
        q0,
        q1,
        q2,
        q3,
        -hq,
        hq,
    )
    # advancing arc: union of the half-circles where v.n >= 0 at x = xa and at x = xb
    # (v.n is linear along a generator), centre dc, half-width dw
    amp_a = _nonzero(v2 + w3 * xa, v3 - w2 * xa)
    amp_b = _nonzero(v2 + w3 * xb, v3 - w2 * xb)
    if amp_a and amp_b:
        ca = 0.5 * (pa0 + pa1)
        dd = 0.5 * (pb0 + pb1) - ca
        dd -= _TWO_PI * math.floor(dd / _TWO_PI + 0.5)
        dc = ca + 0.5 * dd
        dw = _HALF_PI + 0.5 * abs(dd)
    elif amp_a:
        dc = 0.5 * (pa0 + pa1)
        dw = _HALF_PI
    elif amp_b:
        dc = 0.5 * (pb0 + pb1)
        dw = _HALF_PI
    else:
        dc = tdeep
        dw = _PI
    delta = dc - tdeep
    delta -= _TWO_PI * math.floor(delta / _TWO_PI + 0.5)
    # sliver panels (PANEL_SKIP): none at width <= wskip, full weight from 2 wskip, linear between
    wskip = skip * a_any
    # the breakpoints sorted once; a NaN (never a panel's end) as a_any (none either: hi <= a_any)
    srt = _sorted16(bps, a_any)
    for shift in range(-1, 2):
        lo = max(-a_any, delta + _TWO_PI * shift - dw)
        hi = min(a_any, delta + _TWO_PI * shift + dw)
        cur = lo
        j = 0
        while cur < hi:
            # the smallest breakpoint above cur, at most hi (:func:`_next_break`); cur only grows
            while j < 16 and srt[j] <= cur:
                j += 1
            nxt = srt[j] if j < 16 and srt[j] < hi else hi
            width = nxt - cur
            if not (width > wskip):
                cur = nxt
                continue
            ramp = 1.0 if width >= 2.0 * wskip else width / wskip - 1.0
            h = 0.5 * width
            tm = tdeep + 0.5 * (nxt + cur)
            cm = math.cos(tm)
            sm = math.sin(tm)
            # the nodes come in pairs tm -+ a (and tm itself for odd N_T, last): their cosines and
            # sines by the addition theorem, two trigonometric calls a pair; one call site of the
            # (inlined) generator
            ca = 1.0
            sa = 0.0
            for k in range(N_T):
                i = k // 2
                j = N_T - 1 - i  # _GL_NODES[N_T, j] = -_GL_NODES[N_T, i] >= 0
                wgt = R * h * _GL_WEIGHTS[N_T, j] * ramp  # ramp 1.0 (exact) but on slivers
                if i == j:
                    c = cm
                    s = sm
                else:
                    c, s, ca, sa = _paired_node(k, h * _GL_NODES[N_T, j], cm, sm, ca, sa)
                ok, hx, mx, a0, a1, wa, wb = _generator_span(c, s, R, xa, xb, d0, c20, c21, c22, vbody, law)
                gen = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # the generator's moments per unit R dtheta
                if ok:
                    y = R * c
                    z = R * s
                    for ix in range(N_XR):
                        x = mx + hx * _GL_NODES[N_XR, ix]
                        wgx = hx * (wa if ix == 0 else wb)
                        if not (wgx != 0.0):
                            continue
                        # a linear profile without the bank (:func:`.laws._linear_depth_terms`: no reference
                        # counting a point)
                        zeta = a0 + a1 * x
                        if law[LAW_ROW] < 0:
                            depth = _linear_depth_terms(zeta, law)
                        else:
                            depth = _depth_terms(zeta, law, bank)
                        t = _traction_at(x, y, z, 0.0, c, s, depth, v1, v2, v3, w1, w2, w3, law, True)
                        gen = add_point_traction(gen, wgx, x, y, z, t[0], t[1], t[2])
                f1, f2, f3, m1, m2, m3 = add_weighted((f1, f2, f3, m1, m2, m3), wgt, gen)
            cur = nxt
    return f1, f2, f3, m1, m2, m3


@kernel
def _cap(xc, sgn, R, d0, c20, c21, c22, vbody, law, bank, skip=PANEL_SKIP):
    """Moments over the end cap x = xc with outward normal sgn i_M; ``skip`` the sliver u-panels'
    threshold as a fraction of the embedded u-range (default :data:`PANEL_SKIP`; 0: every panel)."""
    v1, v2, v3, w1, w2, w3 = vbody
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    # zeta = e0 + ey y + ez z = e0 + g s, s along the unit direction (dy, dz)
    e0 = d0 - c20 * xc
    ey = -c21
    ez = -c22
    g = math.sqrt(ey * ey + ez * ez)
    if g > 0.0:
        dy = ey / g
        dz = ez / g
        u0 = math.asin(_clip1(-e0 / (g * R)))
    else:
        dy = 1.0
        dz = 0.0
        u0 = -_HALF_PI if e0 > 0.0 else _HALF_PI
    if not (u0 < _HALF_PI):
        return f1, f2, f3, m1, m2, m3
    ty = -dz
    tz = dy
    # v.n = q0 + qy y + qz z = q0 + qs s + qt t
    q0 = sgn * v1
    qy = -sgn * w3
    qz = sgn * w2
    qs = qy * dy + qz * dz
    qt = qy * ty + qz * tz
    # where the delta chord meets the rim: (s, t) = R (sin gam, cos gam)
    ga, gb = _harmonic_roots(q0, R * qt, R * qs)
    ua = math.asin(_clip1(math.sin(ga)))
    ub = math.asin(_clip1(math.sin(gb)))
    ua = min(max(ua, u0), _HALF_PI)
    ub = min(max(ub, u0), _HALF_PI)
    bps = (ua, ub)
    wskip = skip * (_HALF_PI - u0)  # sliver u-panels, as on the lateral surface
    cur = u0
    while cur < _HALF_PI:
        nxt = _next_break(bps, cur, _HALF_PI)
        width = nxt - cur
        if not (width > wskip):
            cur = nxt
            continue
        ramp = 1.0 if width >= 2.0 * wskip else width / wskip - 1.0
        hu = 0.5 * width
        mu = 0.5 * (nxt + cur)
        cm = math.cos(mu)
        sm = math.sin(mu)
        # the nodes come in pairs mu -+ a: their cosines and sines by the addition theorem, two
        # trigonometric calls a pair, as on the lateral surface (issue 34 item 4)
        ca = 1.0
        sa = 0.0
        for k in range(N_U):
            i = k // 2
            jn = N_U - 1 - i  # _GL_NODES[N_U, jn] = -_GL_NODES[N_U, i] > 0 (N_U even)
            cu, su, ca, sa = _paired_node(k, hu * _GL_NODES[N_U, jn], cm, sm, ca, sa)
            sv = R * su
            tl = -R * cu
            th = R * cu
            a0 = q0 + qs * sv
            if qt > 0.0:
                tl = max(tl, -a0 / qt)
            elif qt < 0.0:
                th = min(th, -a0 / qt)
            elif a0 < 0.0:
                continue
            if not (th > tl):
                continue
            ht = 0.5 * (th - tl)
            mt = 0.5 * (th + tl)
            wu = hu * _GL_WEIGHTS[N_U, jn] * R * cu * ramp
            zeta = e0 + g * sv
            # the depth is constant along the chord: once a chord (a linear profile without the bank, as in
            # :func:`_lateral`)
            depth = _linear_depth_terms(zeta, law) if law[LAW_ROW] < 0 else _depth_terms(zeta, law, bank)
            for j in range(N_S):
                t = mt + ht * _GL_NODES[N_S, j]
                wgt = wu * ht * _GL_WEIGHTS[N_S, j]
                y = sv * dy + t * ty
                z = sv * dz + t * tz
                g1, g2, g3 = _traction_at(xc, y, z, sgn, 0.0, 0.0, depth, v1, v2, v3, w1, w2, w3, law, True)
                f1, f2, f3, m1, m2, m3 = add_point_traction(
                    (f1, f2, f3, m1, m2, m3), wgt, xc, y, z, g1, g2, g3
                )
        cur = nxt
    return f1, f2, f3, m1, m2, m3


@small_kernel
def fast_tractions(L, R, chi, c20, c21, c22, d0, vbody, law, bank):
    """Sediment force and torque (body frame, about the COM) by the fixed-cost rule.

    Same arguments and result as :func:`.reference.reference_tractions`:
    ``(c20, c21, c22)`` the E-frame vertical in the body frame, ``d0`` the height of the
    seabed above the COM, ``vbody`` = (v1, v2, v3, w1, w2, w3), ``law`` from
    :func:`.laws.pack_law`. The panels narrower than :data:`PANEL_SKIP` of the embedded arc (the
    caps: u-range) carry no nodes (issue 34 item 4; :func:`fast_tractions_every_panel`: without that).
    """
    return _fast(L, R, chi, c20, c21, c22, d0, vbody, law, bank, PANEL_SKIP)


@small_kernel
def fast_tractions_every_panel(L, R, chi, c20, c21, c22, d0, vbody, law, bank):
    """:func:`fast_tractions` with every lateral panel carrying its nodes, slivers too: the rule of
    main before issue 34 item 4's sliver skip (d09f682), kept for comparison (tests)."""
    return _fast(L, R, chi, c20, c21, c22, d0, vbody, law, bank, 0.0)


@small_kernel
def _fast(L, R, chi, c20, c21, c22, d0, vbody, law, bank, skip):
    """:func:`fast_tractions` with the sliver threshold ``skip`` (:data:`PANEL_SKIP` or 0)."""
    xa = -0.5 * L - chi
    xb = 0.5 * L - chi
    tangential = law[LAW_MU] != 0.0
    f1, f2, f3, m1, m2, m3 = _lateral(R, xa, xb, d0, c20, c21, c22, vbody, law, bank, tangential, skip)
    for k in range(2):
        xc = xb if k == 0 else xa
        sgn = 1.0 if k == 0 else -1.0
        g1, g2, g3, h1, h2, h3 = _cap(xc, sgn, R, d0, c20, c21, c22, vbody, law, bank, skip)
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3
    return f1, f2, f3, m1, m2, m3
