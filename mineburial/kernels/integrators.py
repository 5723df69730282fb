"""Generic pieces of the time integrators: no mine, no sediment, only arrays of floats.

A system (the falling mine of :mod:`.stepper`, or any other) supplies its right-hand
side ``f(y)``; these kernels supply everything else, so that a second system reuses
them instead of forking them. The protocol of one step is:

1. the system evaluates the stages ``k[s] = f(y + h sum_j A[s, j] k[j])``, building the
   stage states with :func:`dopri_stage_state` (the first stage is ``f(y)``, carried
   over from the last step: first same as last, "FSAL");
2. :func:`dopri_solution` gives the new state and the error estimate,
   :func:`error_norm` measures the estimate against the mixed tolerance
   ``atol + rtol max(|y|, |y_new|)`` over vector groups and :func:`next_step_size` chooses the next step
   (accept when the norm is <= 1);
3. :func:`dopri_dense` builds the continuous extension of the accepted step and
   :func:`dense_state` evaluates it anywhere on the step (events, output times).

The fixed-step references (RK4, the seed's local linearisation) get a continuous
extension too: the cubic Hermite interpolant of :func:`hermite_dense` through both ends
and their derivatives, evaluated by the same :func:`dense_state`.

Events are located on the continuous extension by a bracketing root finder (the
Illinois variant of regula falsi, Dowell & Jarratt 1971, BIT 11:168) written in
reverse-communication style: :func:`illinois_next` proposes the next trial fraction
and :func:`illinois_update` takes the event value found there, so the event function
stays the system's own.

Sources: Dormand & Prince (1980), J. Comput. Appl. Math. 6:19 (the 5(4) pair);
Hairer, Norsett & Wanner, *Solving ODEs I*, 2nd ed., sec. II.4 (step-size
control, PI controller with beta = 0.04 after Gustafsson 1991) and II.6 (the dense
output of order 4 used by their code DOPRI5).
"""

import math

import numpy as np

from mineburial._numba import small_kernel

# --- Dormand-Prince 5(4) tableau -------------------------------------------------
N_STAGES = 7
DP_C = np.array([0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0])
DP_A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
        [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
        [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
    ]
)
#: 5th-order weights (the last row of A: first same as last)
DP_B = np.array([35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0])
#: b - b_hat: the error estimate is h sum E_i k_i
DP_E = np.array(
    [71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0]
)
#: coefficients of the 4th-order dense output (Hairer, Norsett & Wanner, DOPRI5 contd5)
DP_D = np.array(
    [
        -12715105075.0 / 11282082432.0,
        0.0,
        87487479700.0 / 32700410799.0,
        -10690763975.0 / 1880347072.0,
        701980252875.0 / 199316789632.0,
        -1453857185.0 / 822651844.0,
        69997945.0 / 29380423.0,
    ]
)

#: PI step-size controller (Hairer, Norsett & Wanner II.4, eqs. (4.12)-(4.13) and DOPRI5)
SAFETY = 0.9
BETA = 0.04
MAX_GROWTH = 10.0
MAX_SHRINK = 0.2
#: error norm floor of the PI memory (DOPRI5)
ERR_FLOOR = 1e-4


@small_kernel
def dopri_stage_state(y, k, s, h, out):
    """out = y + h sum_{j<s} A[s, j] k[j]: the state at which stage ``s`` is evaluated."""
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        for j in range(s):
            acc += DP_A[s, j] * k[j, i]
        out[i] = y[i] + h * acc


@small_kernel
def dopri_solution(y, k, h, out, err):
    """5th-order solution ``out`` and local error estimate ``err`` from the 7 stages
    (stage 6 is f(out) only after the system has evaluated it; its weight in the
    solution is 0, so ``out`` equals the state of stage 6)."""
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        e = 0.0
        for j in range(N_STAGES):
            acc += DP_B[j] * k[j, i]
            e += DP_E[j] * k[j, i]
        out[i] = y[i] + h * acc
        err[i] = h * e


@small_kernel
def error_norm(y, ynew, err, groups, rtol, atol):
    """RMS over the vector groups of |err_g| / (atol + rtol max(|y_g|, |ynew_g|)).

    ``groups`` is a tuple of (start, stop) index ranges, each measured as one Euclidean
    vector (a position, a velocity, a quaternion), so that the norm, and with it every
    step size, is invariant under a rotation of the frame; components outside every
    group (e.g. work accumulators) ride along uncontrolled.
    """
    acc = 0.0
    for g in groups:
        e2 = 0.0
        a2 = 0.0
        b2 = 0.0
        for i in range(g[0], g[1]):
            e2 += err[i] * err[i]
            a2 += y[i] * y[i]
            b2 += ynew[i] * ynew[i]
        sc = atol + rtol * math.sqrt(max(a2, b2))
        acc += e2 / (sc * sc)
    return math.sqrt(acc / len(groups))


@small_kernel
def next_step_size_order(h, err, err_prev, accepted_before, k):
    """:func:`next_step_size` for an error estimate of local order ``k`` (err ~ h^k):
    the PI exponents are 1/k - 0.75 beta and beta (Hairer & Wanner, *Solving ODEs II*,
    sec. IV.2, after Gustafsson 1991). ``k = 5`` is Dormand-Prince 5(4), ``k = 3`` the
    Rosenbrock-W pair ROS34PW2 3(2)."""
    if not (err == err):
        return h * MAX_SHRINK, False, err_prev
    e = max(err, 1e-12)
    fac11 = e ** (1.0 / k - 0.75 * BETA)
    if err <= 1.0:
        fac = fac11 / err_prev**BETA / SAFETY
        fac = min(1.0 / MAX_SHRINK, max(1.0 / MAX_GROWTH, fac))
        hn = h / fac
        if not accepted_before:
            hn = min(hn, h)
        return hn, True, max(err, ERR_FLOOR)
    fac = min(1.0 / MAX_SHRINK, fac11 / SAFETY)
    return h / fac, False, err_prev


@small_kernel
def next_step_size(h, err, err_prev, accepted_before):
    """Step-size factor of the PI controller for Dormand-Prince 5(4) (error order 5):
    returns (h_next, accept, err_memory).

    Accepted (err <= 1): h (err^-0.17 err_prev^0.04) * 0.9, within [0.2, 10] h.
    Rejected: h err^-0.17 * 0.9, at least 0.2 h, and never more than h.
    ``accepted_before``: False right after a rejection (then no growth).
    """
    return next_step_size_order(h, err, err_prev, accepted_before, 5.0)


@small_kernel
def dopri_dense(y, ynew, k, h, r):
    """Coefficients ``r`` (5 x n) of the 4th-order continuous extension of an accepted
    Dormand-Prince step (k[6] = f(ynew))."""
    n = y.shape[0]
    for i in range(n):
        ydiff = ynew[i] - y[i]
        bspl = h * k[0, i] - ydiff
        r[0, i] = y[i]
        r[1, i] = ydiff
        r[2, i] = bspl
        r[3, i] = ydiff - h * k[6, i] - bspl
        acc = 0.0
        for j in range(N_STAGES):
            acc += DP_D[j] * k[j, i]
        r[4, i] = h * acc


@small_kernel
def hermite_dense(y, ynew, f0, f1, h, r):
    """Coefficients ``r`` (5 x n) of the cubic Hermite interpolant through (y, f0) and
    (ynew, f1), in the same form as :func:`dopri_dense` (r[4] = 0)."""
    n = y.shape[0]
    for i in range(n):
        ydiff = ynew[i] - y[i]
        bspl = h * f0[i] - ydiff
        r[0, i] = y[i]
        r[1, i] = ydiff
        r[2, i] = bspl
        r[3, i] = ydiff - h * f1[i] - bspl
        r[4, i] = 0.0


@small_kernel
def dense_state(r, theta, out):
    """State at fraction ``theta`` of the step from the continuous extension ``r``:
    y = r0 + theta (r1 + (1 - theta) (r2 + theta (r3 + (1 - theta) r4)))."""
    n = out.shape[0]
    s1 = 1.0 - theta
    for i in range(n):
        out[i] = r[0, i] + theta * (r[1, i] + s1 * (r[2, i] + theta * (r[3, i] + s1 * r[4, i])))


# --- event location: Illinois regula falsi, reverse communication -----------------
@small_kernel
def illinois_next(a, ga, b, gb):
    """Next trial fraction in the bracket [a, b] with event values ga, gb of opposite
    sign (regula falsi; the midpoint if the secant leaves the bracket)."""
    if gb != ga:
        t = b - gb * (b - a) / (gb - ga)
        if t > a and t < b:
            return t
    return 0.5 * (a + b)


@small_kernel
def illinois_update(a, ga, b, gb, t, gt, side):
    """Shrink the bracket with the value ``gt`` at ``t``; the end kept twice in a row has
    its value halved (Illinois). ``side``: which end was kept last (-1 a, +1 b, 0 none).
    Returns (a, ga, b, gb, side)."""
    if (gt > 0.0) == (gb > 0.0):
        # the root lies in [a, t]
        b = t
        gb = gt
        if side == -1:
            ga *= 0.5
        side = -1
    else:
        a = t
        ga = gt
        if side == 1:
            gb *= 0.5
        side = 1
    return a, ga, b, gb, side


# --- ROS34PW2: a Rosenbrock-W method for the stiff phases ----------------------------
# Rang & Angermann (2005), BIT Numer. Math. 45:761, "New Rosenbrock W-methods of order 3
# for partial differential algebraic equations of index 1", method ROS34PW2: 4 stages,
# order 3 with an embedded order-2 solution, L-stable, stiffly accurate, and of order 3
# for ANY matrix J in W = I - h gamma J (a W-method), so that a Jacobian may be reused
# over many steps. One step, in the form of Hairer & Wanner, Solving ODEs II, sec. IV.7:
#     (I - h gamma J) k_i = h f(y + sum_j ALPHA[i, j] k_j) + h J sum_j GAMMA[i, j] k_j
#     y_new = y + sum_i B[i] k_i,    err = sum_i (B[i] - B_HAT[i]) k_i.
ROS_STAGES = 4
ROS_GAMMA_DIAG = 4.3586652150845900e-01
ROS_ALPHA = np.array(
    [
        [0.0, 0.0, 0.0],
        [8.7173304301691801e-01, 0.0, 0.0],
        [8.4457060015369423e-01, -1.1299064236484185e-01, 0.0],
        [0.0, 0.0, 1.0],
    ]
)
ROS_GAMMA = np.array(
    [
        [0.0, 0.0, 0.0],
        [-8.7173304301691801e-01, 0.0, 0.0],
        [-9.0338057013044082e-01, 5.4180672388095326e-02, 0.0],
        [2.4212380706095346e-01, -1.2232505839045147e00, 5.4526025533510214e-01],
    ]
)
ROS_B = np.array(
    [2.4212380706095346e-01, -1.2232505839045147e00, 1.5452602553351020e00, 4.3586652150845900e-01]
)
ROS_B_HAT = np.array([3.7810903145819369e-01, -9.6042292212423178e-02, 5.0e-01, 2.1793326075422950e-01])
#: local order of the error estimate (embedded order 2): err ~ h^3
ROS_ERROR_ORDER = 3.0


@small_kernel
def ros_stage_state(y, kr, s, out):
    """out = y + sum_{j<s} ALPHA[s, j] k_j: the state of stage ``s``."""
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        for j in range(s):
            acc += ROS_ALPHA[s, j] * kr[j, i]
        out[i] = y[i] + acc


@small_kernel
def ros_coupling(kr, s, cols, z):
    """z = (sum_{j<s} GAMMA[s, j] k_j)[cols]: the coupling's entries in the Jacobian's columns ``cols``,
    the only ones that J, non-zero in those columns, reads (:func:`j_times`; issue 34 item 4: the other
    entries were computed and never read)."""
    m = cols.shape[0]
    for r in range(m):
        acc = 0.0
        for j in range(s):
            acc += ROS_GAMMA[s, j] * kr[j, cols[r]]
        z[r] = acc


@small_kernel
def ros_solution(y, kr, out, err):
    """The order-3 solution and the difference to the embedded order-2 one."""
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        e = 0.0
        for j in range(ROS_STAGES):
            acc += ROS_B[j] * kr[j, i]
            e += (ROS_B[j] - ROS_B_HAT[j]) * kr[j, i]
        out[i] = y[i] + acc
        err[i] = e


# --- W = I - c J with J non-zero in a few columns only -------------------------------
# When only the columns ``cols`` of J are non-zero (the Jacobian with respect to the
# velocities of a mechanical system), W x = b reduces to a system of len(cols)
# unknowns: with z = x[cols], (I - c J[cols, cols]) z = b[cols], and then
# x = b + c J[:, cols] z. ``jc`` holds J[:, cols] (n x m).


#: the LU kernels index with unsigned integers (np.uint64) where a loop does not start at 0: numba wraps a
#: negative signed index around (a[-1] is the last row), a compare-and-add at every access that LLVM
#: removes only where it proves the index non-negative, as it does for range(m) but not for range(c + 1, m)
#: nor a loop counting down (issue 34 item 4); unsigned indices have no wraparound. The arithmetic stays
#: uint64 throughout (uint64 with int64 is float64 in numba, which does not index: a slip fails to compile).
_U1 = np.uint64(1)


@small_kernel
def lu_factor_small(a, piv):
    """In-place LU factorisation with partial pivoting of the m x m matrix ``a``.
    Returns False when a pivot is zero or not finite (singular W: the caller shrinks h)."""
    mu = np.uint64(a.shape[0])
    for c in range(mu):
        p = c
        big = abs(a[c, c])
        for r in range(c + _U1, mu):
            if abs(a[r, c]) > big:
                big = abs(a[r, c])
                p = r
        if not (big > 0.0) or not math.isfinite(big):
            return False
        piv[c] = p
        if p != c:
            for j in range(mu):
                tmp = a[c, j]
                a[c, j] = a[p, j]
                a[p, j] = tmp
        inv = 1.0 / a[c, c]
        for r in range(c + _U1, mu):
            f = a[r, c] * inv
            a[r, c] = f
            for j in range(c + _U1, mu):
                a[r, j] -= f * a[c, j]
    return True


@small_kernel
def lu_solve_small(a, piv, b):
    """Solve in place with the factors of :func:`lu_factor_small`."""
    m = a.shape[0]
    mu = np.uint64(m)
    for c in range(mu):
        p = np.uint64(piv[c])
        if p != c:
            tmp = b[c]
            b[c] = b[p]
            b[p] = tmp
    for r in range(m):
        acc = b[r]
        for j in range(r):
            acc -= a[r, j] * b[j]
        b[r] = acc
    for k in range(mu):
        r = mu - _U1 - k  # m - 1 down to 0
        acc = b[r]
        for j in range(r + _U1, mu):
            acc -= a[r, j] * b[j]
        b[r] = acc / a[r, r]


@small_kernel
def w_factor(jc, cols, c, wa, piv):
    """Factor the reduced W: wa = I - c J[cols, cols]; returns lu_factor_small's flag."""
    m = cols.shape[0]
    for r in range(m):
        row = np.uint64(cols[r])  # loaded once (not again after each store to wa), no wraparound
        for j in range(m):
            wa[r, j] = -c * jc[row, j]
        wa[r, r] += 1.0
    return lu_factor_small(wa, piv)


@small_kernel
def _put(out, i, acc, c, accumulate):
    """out[i] += c acc (``accumulate``) or out[i] = acc."""
    if accumulate:
        out[i] += c * acc
    else:
        out[i] = acc


@small_kernel
def columns_product(jc, z, out, c, accumulate):
    """The product of the Jacobian's columns jc (n x m) with z (m): out = jc z, or out += c jc z with
    ``accumulate`` (what :func:`j_times` and :func:`w_solve` need).

    Four rows at a time (then two, then one): each row's sum is the same sum_j jc[i, j] z[j] from 0.0 in
    the same order (the same floating-point operations), but z[j] is loaded once for four rows and the
    loop over the few columns runs a quarter as often (issue 34 item 4: with m = 6 columns LLVM's unrolled
    loop never ran, and each multiply-add paid a loop's increment, compare and branch)."""
    n = out.shape[0]
    m = jc.shape[1]
    i = 0
    while i + 4 <= n:
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        a3 = 0.0
        for j in range(m):
            zj = z[j]
            a0 += jc[i, j] * zj
            a1 += jc[i + 1, j] * zj
            a2 += jc[i + 2, j] * zj
            a3 += jc[i + 3, j] * zj
        _put(out, i, a0, c, accumulate)
        _put(out, i + 1, a1, c, accumulate)
        _put(out, i + 2, a2, c, accumulate)
        _put(out, i + 3, a3, c, accumulate)
        i += 4
    if i + 2 <= n:
        a0 = 0.0
        a1 = 0.0
        for j in range(m):
            zj = z[j]
            a0 += jc[i, j] * zj
            a1 += jc[i + 1, j] * zj
        _put(out, i, a0, c, accumulate)
        _put(out, i + 1, a1, c, accumulate)
        i += 2
    if i < n:
        acc = 0.0
        for j in range(m):
            acc += jc[i, j] * z[j]
        _put(out, i, acc, c, accumulate)


@small_kernel
def w_solve(jc, cols, c, wa, piv, b, z):
    """Solve W x = b in place (b becomes x) with the factors of :func:`w_factor`."""
    m = cols.shape[0]
    for r in range(m):
        z[r] = b[cols[r]]
    lu_solve_small(wa, piv, z)
    columns_product(jc, z, b, c, True)  # b += c J[:, cols] z


@small_kernel
def j_times(jc, z, out):
    """out = J v for J non-zero in the columns ``cols`` only, from z = v[cols] (as :func:`ros_coupling`
    gives it): jc[:, j] = J[:, cols[j]] (:func:`columns_product`)."""
    columns_product(jc, z, out, 1.0, False)
