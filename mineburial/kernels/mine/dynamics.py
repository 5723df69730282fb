"""Equations of motion of the falling mine: forces, torques and the state derivative.

One function, :func:`derivatives`, evaluates the right-hand side of the
13 equations of motion (plus two work accumulators) for either physics model:

``mineburial`` (default)
    Kirchhoff/Fossen rigid-body equations in the body frame with a strip-theory
    added-mass tensor (seed 001 eqs. (18)-(21), C_M = 1), the gyroscopic and
    Munk terms kept (seed 000 eq. (20) without the eq. (22) simplification),
    exact quadratic cross-flow drag along the rotating body (seed 001 eqs.
    (31)-(47)), axial drag (seed 000 eqs. (38)-(40)), Magnus lift (eqs. (49)-(50))
    and viscous roll damping (eq. (53)).
``impact35``
    The printed model of seed 000 with its typos fixed: linearised drag and lift
    integrals (eqs. (42)-(58)) in the F-frame, no added mass (the ratios f_i of
    eqs. (39)-(58) are never given numbers) and no gyroscopic torque (eq. (22)).

Both share the buoyancy of the body's parts cut by the interfaces (the body protocol's
``cut``; the cylinder's exact volumes of seed 000 eqs. (25)-(36)) and the sediment tractions of
:mod:`mineburial.kernels.mine.sediment` (seed 000 section 6).

Extended state (length :data:`N_EXT`): the 13 physical states of
:mod:`layout`, then the work done on the mine by fluid forces (buoyancy,
drag, lift, added-mass reaction) and by sediment forces, integrated with the
same scheme so that energy bookkeeping closes to the integration error.
"""

import math

from numba.core import types
from numba.extending import overload

from mineburial._numba import JIT_OPTIONS, kernel, small_kernel
from mineburial.kernels.crossflow import quadratic_drag_integrals
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.added_mass import (
    finite_body_cross_drag,
    munk_incidence_factor,
)
from mineburial.kernels.mine.bodies.shapes import DEFAULT_SHAPE
from mineburial.kernels.mine.coefficients import (
    axial_drag_coefficient,
    cross_drag_coefficient,
    lift_coefficient,
    roughness_scaled,
)
from mineburial.kernels.mine.environment import current_velocity
from mineburial.kernels.mine.geometry import e_down_body

# the extended state, the scratch and diagnostics sizes (N_EXT, I_WORK_*, N_WORK, N_DIAG,
# re-exported for the driver) and the phase codes live in kernels.mine.layout
from mineburial.kernels.mine.layout import (
    I_WORK_FLUID,
    I_WORK_SEDIMENT,
    N_DIAG,  # noqa: F401
    P_ADDED_MASS_FACTOR,
    P_CROSSFLOW_FACTOR,
    P_CROSSFLOW_MUNK,
    P_DEPTH,
    P_DRAG,
    P_GRAVITY,
    P_J1,
    P_J2,
    P_MASS,
    P_MODEL,
    P_MUNK,
    P_NU_AIR,
    P_NU_WATER,
    P_RHO_AIR,
    P_RHO_WATER,
    P_SED_RESISTANCE,
    P_WATER_COLUMN,
    PHASE_AIR,
    PHASE_EMBEDDED,
    PHASE_SEABED,
    PHASE_SURFACE,
    PHASE_WATER,
    WC_VISCOUS_CROSSFLOW,
)
from mineburial.kernels.mine.overburden import overburden_below
from mineburial.kernels.mine.sediment import RES_DELTA, sediment_tractions
from mineburial.kernels.mine.sediment.laws import LAW_REFERENCE_PATHS
from mineburial.kernels.rotation import quaternion_rate, rotation_matrix

C_M = 1.0  # transverse added-mass coefficient of a circular section (seed 001 eq. (5), (20))


#: the default shape's body from a parameter vector (``bodies.shapes.DEFAULT_SHAPE``, the cylinder)
_default_body = DEFAULT_SHAPE.kernel().from_params

#: the slot of the packed law (``sediment.laws.pack_law``) after its last, where a drop of a shape
#: other than the default carries a prototype body of its class (:func:`with_shape`)
LAW_SHAPE = LAW_REFERENCE_PATHS + 1


def _shape_class(shape):
    """The body class whose numba type ``shape`` is, or None (the default shape): a NamedTuple
    type of a registered shape, else None, Omitted or nothing."""
    if isinstance(shape, (types.NamedUniTuple, types.NamedTuple)) and shape.instance_class in bodies.SHAPES:
        return shape.instance_class
    return None


def body_of(p, shape):
    """The drop's body from its parameter vector ``p``: the ``from_params`` of the shape whose
    prototype body ``shape`` is (``bodies.shapes.Shape.marker``), of the default shape when
    ``shape`` is None. Compiled code only: the choice is made on the *type* of ``shape``."""
    raise NotImplementedError("compiled code only")


@overload(body_of, jit_options=JIT_OPTIONS, inline="always")
def _overload_body_of(p, shape):
    cls = _shape_class(shape)
    from_params = _default_body if cls is None else bodies.SHAPES[cls].from_params

    def impl(p, shape):
        return from_params(p)

    return impl


def with_shape(law, shape):
    """The packed ``law`` carrying the shape's prototype body ``shape`` (:func:`body_of`) in slot
    :data:`LAW_SHAPE`; the law itself for the default shape (``shape`` None: the law's type, and so
    every kernel compiled for the default shape, unchanged)."""
    raise NotImplementedError("compiled code only")


@overload(with_shape, jit_options=JIT_OPTIONS, inline="always")
def _overload_with_shape(law, shape):
    if _shape_class(shape) is None:

        def unchanged(law, shape):
            return law

        return unchanged

    def carrying(law, shape):
        return law + (shape,)

    return carrying


def drop_body(p, law=None):
    """The mine's body from its parameter vector ``p`` (``layout.P_*``) and its packed law: the
    ``from_params`` of the shape the law carries (:func:`with_shape`; the default shape's when it
    carries none, or without a law): docs/design.md, "Body protocol"."""
    raise NotImplementedError("compiled code only")


@overload(drop_body, jit_options=JIT_OPTIONS, inline="always")
def _overload_drop_body(p, law=None):
    shape = law[LAW_SHAPE] if isinstance(law, types.BaseTuple) and len(law) > LAW_SHAPE else None
    cls = _shape_class(shape)
    from_params = _default_body if cls is None else bodies.SHAPES[cls].from_params

    def impl(p, law=None):
        return from_params(p)

    return impl


def _fluid_hook(body, name):
    """The shape module's own hook ``name`` (``strip_loads``, ``added_mass``, ``cut_moments``), or
    None: the cylinder's strip theory of ``bodies.strip_section``'s radius (or the protocol's
    ``cut``) then."""
    if isinstance(body, (types.NamedUniTuple, types.NamedTuple)) and body.instance_class in bodies.SHAPES:
        return getattr(bodies.SHAPES[body.instance_class], name, None)
    return None


@kernel
def vertical_load(f, fx, fe, dn2, dn3, kb1, kb2, kb3):
    """Body-frame force and torque about the COM of a vertical (E-frame +k) force f
    whose first moments about the COM are fx = f x along i_M and fe = f eta along
    e_down = (0, dn2, dn3); k in the body frame is (kb1, kb2, kb3)."""
    r2 = fe * dn2
    r3 = fe * dn3
    return (f * kb1, f * kb2, f * kb3, r2 * kb3 - r3 * kb2, r3 * kb1 - fx * kb3, fx * kb2 - r2 * kb1)


@kernel
def phase_of(z_lo, z_hi, depth):
    if z_lo >= 0.0:
        return PHASE_AIR
    if z_hi > 0.0:
        return PHASE_SURFACE
    if z_lo >= -depth:
        return PHASE_WATER
    if z_hi > -depth:
        return PHASE_SEABED
    return PHASE_EMBEDDED


@kernel
def strip_forces(rho, nu, R, L, a, b, ur1, ur2, ur3, w1, w2, w3, drag_on, eta, roughness):
    """Fluid force and torque (body frame, about the COM) on the axial strip [a, b].

    ``(ur1, ur2, ur3)`` is the fluid velocity relative to the COM in the body frame.
    The relative normal velocity at station x is v(x) = (ur2 - w3 x, ur3 + w2 x)
    (seed 001 eq. (28)); the cross-flow drag per unit length is
    0.5 rho C_d2 d |v| v (seed 000 eq. (42), exact integral of seed 001
    eqs. (36)-(47)). Axial drag: seed 000 eqs. (38)-(40), scaled by the wetted
    length fraction (b - a)/L. Magnus lift: seed 000 eqs. (49)-(50) with the
    Kutta-Joukowski direction omega x v_body. Roll damping: seed 000 eq. (53).
    ``eta`` is the crossflow efficiency of the viscous-crossflow model applied where eq. (44)
    gives the 2-D cylinder's value (:func:`added_mass.finite_body_cross_drag`); 1 for the
    munk_factor model, which keeps eq. (44) as printed. ``roughness`` is
    ``numerics.crossflow_drag_factor``, the factor on eq. (44) above Re = 150 000
    (:func:`coefficients.roughness_scaled`; 1 keeps it as printed).
    """
    if drag_on == 0 or rho <= 0.0 or b <= a:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    d = 2.0 * R
    ell = b - a
    aspect = L / d
    # axial drag, eq. (38)-(40)
    cd1 = axial_drag_coefficient(aspect)
    f1 = 0.5 * rho * cd1 * math.pi * R * R * abs(ur1) * ur1 * (ell / L)
    # cross-flow drag, exact integrals (seed 001)
    iy, iz, jy, jz = quadratic_drag_integrals(a, b, ur2, ur3, -w3, w2)
    # representative cross-flow speed: rms of |v| over the strip (closed form)
    m1 = 0.5 * (a + b)
    m2 = (a * a + a * b + b * b) / 3.0
    v2sq = (ur2 * ur2 + ur3 * ur3) + 2.0 * m1 * (-ur2 * w3 + ur3 * w2) + m2 * (w3 * w3 + w2 * w2)
    vrms = math.sqrt(max(v2sq, 0.0))
    re = vrms * d / nu
    cd2 = finite_body_cross_drag(roughness_scaled(cross_drag_coefficient(re, aspect), re, roughness), re, eta)
    k = 0.5 * rho * cd2 * d
    f2 = k * iy
    f3 = k * iz
    m2_ = -k * jz
    m3_ = k * jy
    # Magnus lift: f_L = -0.5 rho d C_l |v| (e1 x v), C_l odd in omega1 R / V2
    if vrms > 1e-12:
        cl = lift_coefficient(w1 * R / vrms)
        kl = 0.5 * rho * d * cl
        f2 += kl * iz
        f3 -= kl * iy
        m2_ += kl * jy
        m3_ += kl * jz
    # viscous roll damping, eq. (53): C_m1 = pi mu L d^2 (per wetted length)
    m1_ = -math.pi * rho * nu * ell * d * d * w1
    return f1, f2, f3, m1_, m2_, m3_


@kernel
def impact35_strip_forces(rho, nu, R, L, a, b, ur1, ur2, ur3, w1, w2, w3, drag_on, roughness):
    """Seed 000 printed drag/lift model on the strip [a, b] (body frame, about COM).

    F-frame: i_F = i_M, j_F along the cross-flow V2 at the COM (eq. (12)),
    k_F = i_F x j_F. The strip is the equivalent cylinder of length l = b - a
    whose centre lies at -chi_e = (a + b)/2. Integrals of eqs. (42), (47), (49),
    (54), (55), (57) evaluated exactly for the printed integrands (V2')^2 (not
    |V2'| V2'), which fixes the typos of (56a) (factor 2 on V2 L chi^2) and (58)
    (missing C_l in M_l). Added-mass ratios f_i = 0 (never given in seed 000). ``roughness``:
    as in :func:`strip_forces`.
    """
    if drag_on == 0 or rho <= 0.0 or b <= a:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    d = 2.0 * R
    l = b - a
    c = 0.5 * (a + b)  # centre of the strip = -chi of eq. (42)
    aspect = L / d
    cd1 = axial_drag_coefficient(aspect)
    f1 = 0.5 * rho * cd1 * math.pi * R * R * abs(ur1) * ur1 * (l / L)  # eq. (39)
    v2 = math.sqrt(ur2 * ur2 + ur3 * ur3)
    if v2 > 1e-12:
        jy = ur2 / v2
        jz = ur3 / v2
    else:  # fallback F-frame when the cross-flow vanishes (docs/physics.md): j_F = j_M
        jy = 1.0
        jz = 0.0
    ky = -jz  # k_F = e1 x j_F
    kz = jy
    om2f = w2 * jy + w3 * jz  # eq. (18)
    om3f = w2 * ky + w3 * kz
    # moments of eta over the strip
    s0 = l
    s1 = c * l
    s2 = l * l * l / 12.0 + c * c * l
    s3 = c * l * l * l / 4.0 + c * c * c * l
    re = v2 * d / nu
    cd2 = roughness_scaled(cross_drag_coefficient(re, aspect), re, roughness)
    k = cd2 * R * rho
    # eq. (42)-(43): F_d2 = C_d2 R rho int (V2 - om3f eta)^2 d eta
    fd2 = k * (v2 * v2 * s0 - 2.0 * v2 * om3f * s1 + om3f * om3f * s2)
    # eq. (47)-(48): F_d3 = C_d2 R rho om2f|om2f| (int_0^+ eta^2 - int_-^0 eta^2)
    ea = a
    eb = b
    pos = (max(eb, 0.0) ** 3 - max(ea, 0.0) ** 3) / 3.0
    neg = (min(eb, 0.0) ** 3 - min(ea, 0.0) ** 3) / 3.0
    fd3 = -k * om2f * abs(om2f) * (pos - neg)
    # eq. (49)-(50): lift along -k_F (Kutta-Joukowski sense, see docs/physics.md)
    fl = 0.0
    ml2 = 0.0
    if v2 > 1e-12:
        cl = lift_coefficient(w1 * R / v2)
        kl = cl * R * rho * v2
        fl = -kl * (v2 * s0 - om3f * s1)
        # eq. (57): torque of the lift about j_F: -int eta f_l d eta
        ml2 = kl * (v2 * s1 - om3f * s2)
    # eq. (54): M_d2 = -om2f|om2f| C_d2 R rho int eta^2 |eta|
    e4 = (abs(eb) ** 3 * eb - abs(ea) ** 3 * ea) / 4.0
    md2 = -k * om2f * abs(om2f) * e4
    # eq. (55): M_d3 = C_d2 R rho int (V2 - om3f eta)^2 eta d eta
    md3 = k * (v2 * v2 * s1 - 2.0 * v2 * om3f * s2 + om3f * om3f * s3)
    # eq. (53): viscous roll damping
    m1_ = -math.pi * rho * nu * l * d * d * w1
    # back to body axes
    f2 = fd2 * jy + (fd3 + fl) * ky
    f3 = fd2 * jz + (fd3 + fl) * kz
    mj = md2 + ml2
    m2_ = mj * jy + md3 * ky
    m3_ = mj * jz + md3 * kz
    return f1, f2, f3, m1_, m2_, m3_


@kernel
def add_strip_forces(model, rho, nu, a, b, ur1, ur2, ur3, w1, w2, w3, loads):
    """Add the fluid force and torque on the strip [a, b] of the selected model
    (:func:`impact35_strip_forces` or :func:`strip_forces`) to ``loads`` (body frame, about
    the COM); ``model`` = (impact35, R, L, drag_on, eta, roughness) as in :func:`derivatives`."""
    impact35, R, L, drag_on, eta, roughness = model
    f1, f2, f3, m1, m2, m3 = loads
    if impact35:
        h1, h2, h3, h4, h5, h6 = impact35_strip_forces(
            rho, nu, R, L, a, b, ur1, ur2, ur3, w1, w2, w3, drag_on, roughness
        )
    else:
        h1, h2, h3, h4, h5, h6 = strip_forces(
            rho, nu, R, L, a, b, ur1, ur2, ur3, w1, w2, w3, drag_on, eta, roughness
        )
    return f1 + h1, f2 + h2, f3 + h3, m1 + h4, m2 + h5, m3 + h6


def body_strip_loads(body, model, rho, nu, a, b, ur1, ur2, ur3, w1, w2, w3, loads):
    """The fluid strips of ``[a, b]`` added to ``loads``: the shape's ``strip_loads`` hook, or
    :func:`add_strip_forces` (the strip theory of one section radius, ``model``'s R)."""
    raise NotImplementedError("compiled code only")


@overload(body_strip_loads, jit_options=JIT_OPTIONS, inline="always")
def _overload_body_strip_loads(body, model, rho, nu, a, b, ur1, ur2, ur3, w1, w2, w3, loads):
    own = _fluid_hook(body, "strip_loads")
    if own is not None:
        return own

    def one_radius(body, model, rho, nu, a, b, ur1, ur2, ur3, w1, w2, w3, loads):
        return add_strip_forces(model, rho, nu, a, b, ur1, ur2, ur3, w1, w2, w3, loads)

    return one_radius


def body_cut_moments(body, a_z, z_c, level):
    """Volume and centroid ``(V, x_c, eta_c)`` of the body's part below the plane ``level``: the
    shape's ``cut_moments`` hook (the cut without its wetted areas), or the first three values
    of the protocol's ``bodies.cut``."""
    raise NotImplementedError("compiled code only")


@overload(body_cut_moments, jit_options=JIT_OPTIONS, inline="always")
def _overload_body_cut_moments(body, a_z, z_c, level):
    own = _fluid_hook(body, "cut_moments")
    if own is not None:
        return own

    def by_cut(body, a_z, z_c, level):
        v, x, e, _, _, _ = bodies.cut(body, a_z, z_c, level)
        return v, x, e

    return by_cut


@kernel
def solve6(a, rhs, x):
    """Solve the 6x6 symmetric positive definite system a x = rhs in place (Cholesky).

    ``a`` is a flat 36-array (row-major) overwritten by its factor.
    """
    n = 6
    for j in range(n):
        s = a[j * n + j]
        for k in range(j):
            s -= a[j * n + k] * a[j * n + k]
        s = math.sqrt(s)
        a[j * n + j] = s
        for i in range(j + 1, n):
            t = a[i * n + j]
            for k in range(j):
                t -= a[i * n + k] * a[j * n + k]
            a[i * n + j] = t / s
    for i in range(n):
        t = rhs[i]
        for k in range(i):
            t -= a[i * n + k] * x[k]
        x[i] = t / a[i * n + i]
    for i in range(n - 1, -1, -1):
        t = x[i]
        for k in range(i + 1, n):
            t -= a[k * n + i] * x[k]
        x[i] = t / a[i * n + i]


@small_kernel
def _solve_blocks(m00, m11, m22, m33, m44, m55, m42, m51, rhs):
    """The solution of the generalised mass matrix without pore-pressure added mass, given its
    non-zero entries (the diagonal ``m00 .. m55`` and the U3-W2 and U2-W3 couplings ``m42 = M[4, 2]``,
    ``m51 = M[5, 1]``) and ``rhs`` (6 values): :func:`solve6`'s Cholesky with the products of the
    factor's zeros left out (the same operations on the other entries, in its order), so the same
    values (up to the sign of a zero result), without its ~90 multiply-subtracts of zeros."""
    l00 = math.sqrt(m00)
    l11 = math.sqrt(m11)
    l22 = math.sqrt(m22)
    l33 = math.sqrt(m33)
    l42 = m42 / l22
    l44 = math.sqrt(m44 - l42 * l42)
    l51 = m51 / l11
    l55 = math.sqrt(m55 - l51 * l51)
    # forward substitution, then back substitution (solve6's order)
    y0 = rhs[0] / l00
    y1 = rhs[1] / l11
    y2 = rhs[2] / l22
    y3 = rhs[3] / l33
    y4 = (rhs[4] - l42 * y2) / l44
    y5 = (rhs[5] - l51 * y1) / l55
    x5 = y5 / l55
    x4 = y4 / l44
    return y0 / l00, (y1 - l51 * x5) / l11, (y2 - l42 * x4) / l22, y3 / l33, x4, x5


@small_kernel
def _solve_mass(mass, rhs, x, added_pore):
    """:func:`solve6` of the generalised mass matrix of :func:`_mass_matrix` into ``x``: by its
    blocks (:func:`_solve_blocks`) when there is no pore-pressure added mass, where the matrix
    couples only U2 with W3 and U3 with W2."""
    if added_pore > 0.0:
        solve6(mass, rhs, x)
        return
    x0, x1, x2, x3, x4, x5 = _solve_blocks(
        mass[0], mass[7], mass[14], mass[21], mass[28], mass[35], mass[4 * 6 + 2], mass[5 * 6 + 1], rhs
    )
    x[0] = x0
    x[1] = x1
    x[2] = x2
    x[3] = x3
    x[4] = x4
    x[5] = x5


# ---------------------------------------------------------------------------------------------
# the right-hand side, in pieces, each inlined into derivatives at numba's IR level (one call site
# each). Measured (docs/design.md, "Developing kernels"): as kernels, 1,000 drops took ~8 % more
# CPU and the extra units are linked again at every compiled level above
# ---------------------------------------------------------------------------------------------
@small_kernel
def _immersed_parts(body, a_z, z, depth, z_lo, v_total):
    """The body cut by the two interfaces (seed 000 section 4): volume and first moments
    ``vs, xs, es`` of the part below the water surface (water and embedded parts together),
    ``vb, xb, eb`` of the part below the seabed (the overburden's top cut,
    :func:`.overburden.overburden_below`), and the volumes ``va`` of the air part and ``vw``
    of the water part."""
    vs, xs, es = body_cut_moments(body, a_z, z, 0.0)
    vb = 0.0
    xb = 0.0
    eb = 0.0
    if z_lo < -depth:
        vb, xb, eb = body_cut_moments(body, a_z, z, -depth)
    va = v_total - vs
    if va < 0.0:
        va = 0.0
    vw = vs - vb
    if vw < 0.0:
        vw = 0.0
    return vs, xs, es, vb, xb, va, vw, eb


@small_kernel
def _buoyancy(rho_w, rho_a, g, vs, xs, es, va, v_total, x_total, dn2, dn3, kb1, kb2, kb3):
    """Buoyancy (seed 000 eqs. (34)-(36)), body frame about the COM: water on everything below
    the surface, air on the part above it; each acts at its partial centre of volume (the air
    part's first moments follow from the whole body's minus the immersed part's)."""
    fw = rho_w * g * vs
    fa = rho_a * g * va
    return vertical_load(
        fw + fa,
        fw * xs + rho_a * g * (v_total * x_total - vs * xs),
        fw * es - rho_a * g * vs * es,
        dn2,
        dn3,
        kb1,
        kb2,
        kb3,
    )


@small_kernel
def _water_part_loads(body, p, current_bank, model, r, z, a_z, u, w, parts, v_total, loads):
    """Drag, lift and roll damping of the water part (below the surface and above the seabed,
    as its equivalent cylinder, seed 000 section 4.1) in the current at the height of the
    part's centre, added to ``loads``. Also returns the part's axial span ``(wa, wb)`` (for its
    added mass) and the current in the body frame (zero when no part is in the water)."""
    vs, xs, _, vb, xb, _, vw, _ = parts
    wa = 0.0
    wb = 0.0
    cur = (0.0, 0.0, 0.0)
    if vw > 1e-15 * v_total:
        xw = (vs * xs - vb * xb) / vw
        _, wa, wb, _ = bodies.equivalent_part(body, vw, xw, 0.0)
        # current at the height of the water part's centre
        zc_w = z + a_z * xw
        cu, cv = current_velocity(zc_w, p, current_bank)
        ur1 = r[0] * cu + r[3] * cv - u[0]
        ur2 = r[1] * cu + r[4] * cv - u[1]
        ur3 = r[2] * cu + r[5] * cv - u[2]
        loads = body_strip_loads(
            body, model, p[P_RHO_WATER], p[P_NU_WATER], wa, wb, ur1, ur2, ur3, w[0], w[1], w[2], loads
        )
        cur = (r[0] * cu + r[3] * cv, r[1] * cu + r[4] * cv, r[2] * cu + r[5] * cv)
    return loads, wa, wb, cur


@small_kernel
def _air_part_loads(body, p, model, u, w, parts, v_total, x_total, loads):
    """Drag, lift and roll damping of the part above the water surface (still air), added to
    ``loads``; also returns the part's axial span ``(aa, ab)``."""
    vs, xs, _, _, _, va, _, _ = parts
    aa = 0.0
    ab = 0.0
    if va > 1e-15 * v_total and p[P_RHO_AIR] > 0.0:
        xa_c = (v_total * x_total - vs * xs) / va
        _, aa, ab, _ = bodies.equivalent_part(body, va, xa_c, 0.0)
        loads = body_strip_loads(
            body, model, p[P_RHO_AIR], p[P_NU_AIR], aa, ab, -u[0], -u[1], -u[2], w[0], w[1], w[2], loads
        )
    return loads, aa, ab


@small_kernel
def _sediment_loads(body, p, law, sediment_bank, r, y, a_z, z, z_lo, depth, dn2, dn3, kb, parts, loads):
    """Sediment tractions (seed 000 section 6) and, unless the resistance is the delta law, the
    geostatic effective overburden on every embedded element (closed form; its top cut is the
    part below the seabed in ``parts``, :func:`_immersed_parts`), added to ``loads``
    (body frame). Also returns the sediment's force (E-frame), its torque (body frame) and the
    pore-pressure added mass; all zero when no part is below the seabed."""
    kb1, kb2, kb3 = kb
    rho_w = p[P_RHO_WATER]
    g = p[P_GRAVITY]
    fb1, fb2, fb3, mb1, mb2, mb3 = loads
    sf1 = 0.0
    sf2 = 0.0
    sf3 = 0.0
    sm1 = 0.0
    sm2 = 0.0
    sm3 = 0.0
    added_pore = 0.0
    if z_lo < -depth:
        sf1, sf2, sf3, sm1, sm2, sm3, added_pore = sediment_tractions(
            body, r, (y[0], y[1], y[2]), (y[3], y[4], y[5]), (y[10], y[11], y[12]), -depth, law, sediment_bank
        )
        if int(p[P_SED_RESISTANCE]) != RES_DELTA:
            # geostatic effective overburden on every embedded element (closed form)
            below = (parts[3], parts[4], parts[7])  # bodies.cut(body, a_z, z, -depth)
            fo, fox, foe = overburden_below(
                body, a_z, z, -depth, z_lo, rho_w, g, p, sediment_bank, law, below
            )
            sf3 += fo
            _, _, _, t1, t2, t3 = vertical_load(fo, fox, foe, dn2, dn3, kb1, kb2, kb3)
            sm1 += t1
            sm2 += t2
            sm3 += t3
        fb1 += r[0] * sf1 + r[3] * sf2 + r[6] * sf3
        fb2 += r[1] * sf1 + r[4] * sf2 + r[7] * sf3
        fb3 += r[2] * sf1 + r[5] * sf2 + r[8] * sf3
        mb1 += sm1
        mb2 += sm2
        mb3 += sm3
    return (fb1, fb2, fb3, mb1, mb2, mb3), (sf1, sf2, sf3, sm1, sm2, sm3), added_pore


@small_kernel
def _added_mass(body, p, model, crossflow_model, wa, wb, aa, ab):
    """Added mass of the wetted parts, ``(a0, a1, a2, a11)``: the zeroth, first and second
    moments about the COM of the transverse added mass per unit length along the axis, and
    the axial added mass (none in the impact35 model)."""
    impact35, R, _, _, _, _ = model
    rho_w = p[P_RHO_WATER]
    rho_a = p[P_RHO_AIR]
    # strip-theory added mass per unit length a = C_M rho pi R^2 (seed 001 eqs. (20)-(21))
    a0 = 0.0
    a1 = 0.0
    a2 = 0.0
    if not impact35:
        if wb > wa:
            aw = C_M * rho_w * math.pi * R * R
            a0 += aw * (wb - wa)
            a1 += aw * 0.5 * (wb * wb - wa * wa)
            a2 += aw * (wb * wb * wb - wa * wa * wa) / 3.0
        if ab > aa:
            aair = C_M * rho_a * math.pi * R * R
            a0 += aair * (ab - aa)
            a1 += aair * 0.5 * (ab * ab - aa * aa)
            a2 += aair * (ab * ab * ab - aa * aa * aa) / 3.0
    if crossflow_model:
        # finite closed cylinder (BEM tables, kernels/mine/added_mass.py) on the strip values
        # (a0 = rho V of the wetted interval): transverse k_t and axial k_a of rho V; the
        # rotational inertia k_r of strip theory's about the wetted centroid, moved to the
        # COM with the transverse mass (parallel axes; docs/physics.md)
        kt, ka, kr = bodies.finite_added_mass(body)
        a11 = ka * a0
        if a0 > 0.0:
            shift = a1 * a1 / a0
            a2 = kr * (a2 - shift) + kt * shift
        a0 *= kt
        a1 *= kt
    else:
        # axial added mass: the Munk moment of a body of transverse added mass a0 and
        # axial added mass a11 is (a0 - a11) U1 U2; munk_factor = 1 keeps the
        # slender-body value a11 = 0, munk_factor = 0 makes the translational added
        # mass isotropic and removes it (docs/physics.md, "added mass").
        a11 = (1.0 - p[P_MUNK]) * a0
    # numerics.added_mass_factor on every coefficient (a calibration input, issue 32; 1.0
    # leaves the potential-flow values bit for bit)
    c = p[P_ADDED_MASS_FACTOR]
    return c * a0, c * a1, c * a2, c * a11


def body_added_mass(body, p, model, crossflow_model, wa, wb, aa, ab):
    """The wetted parts' added mass ``(a0, a1, a2, a11)``: the shape's ``added_mass`` hook, or
    :func:`_added_mass` (strip theory of one section radius and the finite body's factors)."""
    raise NotImplementedError("compiled code only")


@overload(body_added_mass, jit_options=JIT_OPTIONS, inline="always")
def _overload_body_added_mass(body, p, model, crossflow_model, wa, wb, aa, ab):
    own = _fluid_hook(body, "added_mass")
    if own is not None:
        return own

    def one_radius(body, p, model, crossflow_model, wa, wb, aa, ab):
        return _added_mass(body, p, model, crossflow_model, wa, wb, aa, ab)

    return one_radius


@small_kernel
def _mass_matrix(mass, m, J1, J2, added, added_pore, kb):
    """The generalised mass matrix (body frame, order U1 U2 U3 W1 W2 W3; flat 36, row-major)
    of the rigid body, its added mass and the pore-pressure added mass along the vertical."""
    a0, a1, a2, a11 = added
    for i in range(36):
        mass[i] = 0.0
    mass[0] = m + a11
    mass[7] = m + a0
    mass[14] = m + a0
    mass[21] = J1
    mass[28] = J2 + a2
    mass[35] = J2 + a2
    mass[1 * 6 + 5] = a1
    mass[5 * 6 + 1] = a1
    mass[2 * 6 + 4] = -a1
    mass[4 * 6 + 2] = -a1
    if added_pore > 0.0:
        for i in range(3):
            for j in range(3):
                mass[i * 6 + j] += added_pore * kb[i] * kb[j]


@small_kernel
def _momentum_rhs(loads, m, J1, J2, model, crossflow_model, munk_fraction, added, u, w, cur):
    """Right side of the Kirchhoff equations M dnu/dt = rhs (body frame): the loads less the
    rigid-body Coriolis/gyroscopic terms and the added mass's Kirchhoff terms, for the velocity
    relative to a current steady in the E-frame. Returns it (6 values) and the rigid-body terms
    C_RB(nu) nu (the work rates need them)."""
    impact35 = model[0]
    a0, a1, a2, a11 = added
    u1, u2, u3 = u
    w1, w2, w3 = w
    fb1, fb2, fb3, mb1, mb2, mb3 = loads
    # relative velocity for the added-mass terms (current assumed uniform in time)
    vr1 = u1 - cur[0]
    vr2 = u2 - cur[1]
    vr3 = u3 - cur[2]
    # added-mass momenta P_A, H_A = M_A nu_r
    pa1 = a11 * vr1
    pa2 = a0 * vr2 + a1 * w3
    pa3 = a0 * vr3 - a1 * w2
    ha1 = 0.0
    ha2 = -a1 * vr3 + a2 * w2
    ha3 = a1 * vr2 + a2 * w3
    # Kirchhoff terms  C_A(nu_r) nu_r = [w x P_A ; w x H_A + v_r x P_A]
    ca1 = w2 * pa3 - w3 * pa2
    ca2 = w3 * pa1 - w1 * pa3
    ca3 = w1 * pa2 - w2 * pa1
    ca4 = (w2 * ha3 - w3 * ha2) + (vr2 * pa3 - vr3 * pa2)
    ca5 = (w3 * ha1 - w1 * ha3) + (vr3 * pa1 - vr1 * pa3)
    ca6 = (w1 * ha2 - w2 * ha1) + (vr1 * pa2 - vr2 * pa1)
    if crossflow_model:
        # viscous-crossflow method (Allen & Perkins 1951; Jorgensen NASA TR R-474; DATCOM bodyjm.f):
        # the potential (Munk) part, (a0 - a11) U1 U_perp, carries the factor cos(alpha/2),
        # and numerics.crossflow_munk_fraction f of it is kept (1: Jorgensen's full moment;
        # 0: none, the tuned removal of the munk_factor model; issue 32's continuous Munk
        # fraction). The rest is removed with its force partner w x ((a0 - a11) U_perp), so
        # the pair stays power-free (energy conserved without drag); the separated crossflow
        # eta C_dc sin^2(alpha) q A_p is the strip drag with eta (strip_forces).
        cut = (1.0 - munk_fraction * munk_incidence_factor(vr1, vr2, vr3)) * (a0 - a11)
        ca1 -= cut * (w2 * vr3 - w3 * vr2)
        ca2 -= cut * (-w1 * vr3)
        ca3 -= cut * (w1 * vr2)
        ca5 -= cut * (-vr1 * vr3)
        ca6 -= cut * (vr1 * vr2)
    # d(nu_c)/dt in the body frame for a current steady in the E-frame: -w x U_c
    dc1 = -(w2 * cur[2] - w3 * cur[1])
    dc2 = -(w3 * cur[0] - w1 * cur[2])
    dc3 = -(w1 * cur[1] - w2 * cur[0])
    mdc1 = a11 * dc1
    mdc2 = a0 * dc2
    mdc3 = a0 * dc3
    mdc5 = -a1 * dc3
    mdc6 = a1 * dc2
    # rigid-body Coriolis/gyroscopic terms C_RB(nu) nu = [m w x U ; w x J w]
    cr1 = m * (w2 * u3 - w3 * u2)
    cr2 = m * (w3 * u1 - w1 * u3)
    cr3 = m * (w1 * u2 - w2 * u1)
    if impact35:
        cr4 = 0.0  # apparent torque neglected, seed 000 eq. (22)
        cr5 = 0.0
        cr6 = 0.0
    else:
        cr4 = w2 * (J2 * w3) - w3 * (J2 * w2)
        cr5 = w3 * (J1 * w1) - w1 * (J2 * w3)
        cr6 = w1 * (J2 * w2) - w2 * (J1 * w1)
    rhs = (
        fb1 - cr1 - ca1 + mdc1,
        fb2 - cr2 - ca2 + mdc2,
        fb3 - cr3 - ca3 + mdc3,
        mb1 - cr4 - ca4,
        mb2 - cr5 - ca5 + mdc5,
        mb3 - cr6 - ca6 + mdc6,
    )
    return rhs, (cr1, cr2, cr3, cr4, cr5, cr6)


@small_kernel
def _state_rates(dy, y, r, q, u, w, dnu):
    """dy/dt of the 13 physical states: position, E-frame velocity dV/dt = R (dU/dt + w x U),
    quaternion and angular velocity, from the body-frame accelerations ``dnu``."""
    u1, u2, u3 = u
    w1, w2, w3 = w
    dy[0] = y[3]
    dy[1] = y[4]
    dy[2] = y[5]
    ab1 = dnu[0] + (w2 * u3 - w3 * u2)
    ab2 = dnu[1] + (w3 * u1 - w1 * u3)
    ab3 = dnu[2] + (w1 * u2 - w2 * u1)
    dy[3] = r[0] * ab1 + r[1] * ab2 + r[2] * ab3
    dy[4] = r[3] * ab1 + r[4] * ab2 + r[5] * ab3
    dy[5] = r[6] * ab1 + r[7] * ab2 + r[8] * ab3
    dq0, dq1, dq2, dq3 = quaternion_rate(q[0], q[1], q[2], q[3], w1, w2, w3)
    dy[6] = dq0
    dy[7] = dq1
    dy[8] = dq2
    dy[9] = dq3
    dy[10] = dnu[3]
    dy[11] = dnu[4]
    dy[12] = dnu[5]


@small_kernel
def _work_rates(dy, r, m, g, J1, J2, kb, u, w, dnu, crb, sed):
    """Work rates of the sediment (its force on the COM velocity plus its torque on omega) and
    of the fluid: everything that is neither gravity nor sediment, including the added-mass
    reaction (m dU/dt + C_RB - gravity - sediment). Returns the fluid's force on the body
    (body frame), which the diagnostics report in the E-frame."""
    u1, u2, u3 = u
    w1, w2, w3 = w
    sf1, sf2, sf3, sm1, sm2, sm3 = sed
    cr1, cr2, cr3, cr4, cr5, cr6 = crb
    sed_t1 = r[0] * sf1 + r[3] * sf2 + r[6] * sf3
    sed_t2 = r[1] * sf1 + r[4] * sf2 + r[7] * sf3
    sed_t3 = r[2] * sf1 + r[5] * sf2 + r[8] * sf3
    sed_power = sed_t1 * u1 + sed_t2 * u2 + sed_t3 * u3 + sm1 * w1 + sm2 * w2 + sm3 * w3
    ft1 = m * dnu[0] + cr1 + m * g * kb[0] - sed_t1
    ft2 = m * dnu[1] + cr2 + m * g * kb[1] - sed_t2
    ft3 = m * dnu[2] + cr3 + m * g * kb[2] - sed_t3
    mt1 = J1 * dnu[3] + cr4
    mt2 = J2 * dnu[4] + cr5
    mt3 = J2 * dnu[5] + cr6
    mt1 -= sm1
    mt2 -= sm2
    mt3 -= sm3
    dy[I_WORK_FLUID] = ft1 * u1 + ft2 * u2 + ft3 * u3 + mt1 * w1 + mt2 * w2 + mt3 * w3
    dy[I_WORK_SEDIMENT] = sed_power
    return ft1, ft2, ft3


@kernel
def derivatives(y, p, law, sediment_bank, current_bank, work, dy, diag):
    """Right-hand side dy/dt of the extended state ``y`` (length N_EXT).

    ``law`` is the drop's sediment law, packed once (:func:`sediment.pack_law`).
    ``work`` is a scratch array of N_WORK floats, ``diag`` receives N_DIAG
    diagnostics: fluid force (E-frame, 3), sediment force (E-frame, 3), total
    torque (body, 3), immersed volume, embedded volume, phase, z_lo, z_hi,
    added mass (transverse, water), pore-pressure added mass.
    Returns the phase code.

    The loads (body frame, about the COM) are summed in this order: buoyancy, the water
    part's and the air part's fluid forces, the sediment's, gravity; then the added mass, the
    generalised mass matrix and the Kirchhoff equations give the accelerations.
    """
    body = drop_body(p, law)  # the law carries the shape (with_shape)
    R, L = bodies.strip_section(body)  # of the strip theory (docs/design.md, "Body protocol")
    m = p[P_MASS]
    J1 = p[P_J1]
    J2 = p[P_J2]
    g = p[P_GRAVITY]
    depth = p[P_DEPTH]
    crossflow_model = int(p[P_WATER_COLUMN]) == WC_VISCOUS_CROSSFLOW
    # separated crossflow efficiency of the viscous-crossflow model (DATCOM bodyrt.f)
    eta = bodies.crossflow_efficiency(body) if crossflow_model else 1.0
    # what add_strip_forces needs; the last, numerics.crossflow_drag_factor (eq. (44) above Re 150 000)
    model = (int(p[P_MODEL]) == 1, R, L, int(p[P_DRAG]), eta, p[P_CROSSFLOW_FACTOR])

    qn = math.sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8] + y[9] * y[9])
    q = (y[6] / qn, y[7] / qn, y[8] / qn, y[9] / qn)
    w = (y[10], y[11], y[12])
    r = rotation_matrix(q[0], q[1], q[2], q[3])
    # body components of a world vector: R^T v ; rows of R^T are columns of R
    a_z = r[6]  # i_M . k
    kb = (r[6], r[7], r[8])  # k in body frame
    u = (  # body-frame COM velocity
        r[0] * y[3] + r[3] * y[4] + r[6] * y[5],
        r[1] * y[3] + r[4] * y[4] + r[7] * y[5],
        r[2] * y[3] + r[5] * y[4] + r[8] * y[5],
    )
    z = y[2]
    v_total, x_total = bodies.volume(body)
    z_lo, z_hi = bodies.extent(body, a_z, z)
    phase = phase_of(z_lo, z_hi, depth)
    parts = _immersed_parts(body, a_z, z, depth, z_lo, v_total)
    # unit vector e_down in the body frame: projection of -k normal to the axis
    _, dn2, dn3 = e_down_body(kb[0], kb[1], kb[2])

    vs, xs, es, vb, _, va, _, _ = parts
    loads = _buoyancy(
        p[P_RHO_WATER], p[P_RHO_AIR], g, vs, xs, es, va, v_total, x_total, dn2, dn3, kb[0], kb[1], kb[2]
    )
    loads, wa, wb, cur = _water_part_loads(
        body, p, current_bank, model, r, z, a_z, u, w, parts, v_total, loads
    )
    loads, aa, ab = _air_part_loads(body, p, model, u, w, parts, v_total, x_total, loads)
    loads, sed, added_pore = _sediment_loads(
        body, p, law, sediment_bank, r, y, a_z, z, z_lo, depth, dn2, dn3, kb, parts, loads
    )
    fb1, fb2, fb3, mb1, mb2, mb3 = loads
    # gravity (E-frame -k), no torque about the COM
    fb1 -= m * g * kb[0]
    fb2 -= m * g * kb[1]
    fb3 -= m * g * kb[2]
    loads = (fb1, fb2, fb3, mb1, mb2, mb3)

    added = body_added_mass(body, p, model, crossflow_model, wa, wb, aa, ab)
    rhs, crb = _momentum_rhs(loads, m, J1, J2, model, crossflow_model, p[P_CROSSFLOW_MUNK], added, u, w, cur)
    if added_pore > 0.0:
        # the full 6x6 solve in the work array (the vertical's pore-pressure mass couples all of U)
        mass = work[0:36]
        rhs_a = work[36:42]
        dnu_a = work[42:48]
        _mass_matrix(mass, m, J1, J2, added, added_pore, kb)
        rhs_a[0] = rhs[0]
        rhs_a[1] = rhs[1]
        rhs_a[2] = rhs[2]
        rhs_a[3] = rhs[3]
        rhs_a[4] = rhs[4]
        rhs_a[5] = rhs[5]
        solve6(mass, rhs_a, dnu_a)
        dnu = (dnu_a[0], dnu_a[1], dnu_a[2], dnu_a[3], dnu_a[4], dnu_a[5])  # dU/dt, dW/dt (body frame)
    else:
        # _mass_matrix's non-zero entries, the same sums, solved by its blocks (_solve_mass)
        a0, a1, a2, a11 = added
        dnu = _solve_blocks(m + a11, m + a0, m + a0, J1, J2 + a2, J2 + a2, -a1, a1, rhs)
    _state_rates(dy, y, r, q, u, w, dnu)
    ft1, ft2, ft3 = _work_rates(dy, r, m, g, J1, J2, kb, u, w, dnu, crb, sed)

    # diagnostics
    diag[0] = r[0] * ft1 + r[1] * ft2 + r[2] * ft3
    diag[1] = r[3] * ft1 + r[4] * ft2 + r[5] * ft3
    diag[2] = r[6] * ft1 + r[7] * ft2 + r[8] * ft3
    diag[3] = sed[0]
    diag[4] = sed[1]
    diag[5] = sed[2]
    diag[6] = mb1
    diag[7] = mb2
    diag[8] = mb3
    diag[9] = vs
    diag[10] = vb
    diag[11] = phase
    diag[12] = z_lo
    diag[13] = z_hi
    diag[14] = added[0]
    diag[15] = added_pore
    return phase
