"""Added mass of closed bodies of revolution (frusta: a cone, the cylinder, and between) by the
boundary-element package capytaine, as ``benchmarks/added_mass_bem.py`` computed the closed
cylinder's table (capytaine 3.0.0, NOT a project dependency: run it in a separate environment,
``pip install capytaine==3.0.0``).

Unbounded fluid (``free_surface = inf``: Rankine Green function only, frequency-independent),
rho = 1, direct method (the cylinder script's choice: it converges faster on the sphere). The body
is a closed surface of revolution about the z axis, meshed by revolving a meridian polyline (base
cap, flank, top cap; spacing refined towards the rims) ``N_THETA`` times.

For each body it prints the added-mass coefficients that ``kernels/mine/added_mass.py``'s frustum
table holds (``FRUSTUM_*``): with V the volume, x_v its centroid on the axis and strip theory's
``a(x) = rho pi r(x)^2`` (seed 001 eqs. (20)-(21)),

* ``k_a = m_axial / (rho V)`` (heave on the z axis);
* ``k_t = m_transverse / (rho V)`` (surge);
* ``delta = (x_m - x_v) / L``: the centre of added mass ``x_m = x_v + m_{surge,pitch} /
  m_surge`` (pitch about the centroid moves a station at height ``z`` by ``Omega z`` along x,
  so the coupling is ``int a z`` about it) less the centroid, positive towards the top (the nose);
  0 for a fore-aft symmetric body;
* ``k_r``: the added moment of inertia about a transverse axis through ``x_m``
  (``m_pitch - m_{surge,pitch}^2 / m_surge``) as a fraction of strip theory's about the centroid,
  ``rho pi int r^2 (x - x_v)^2 dx`` (for the cylinder ``rho pi R^2 L^3 / 12``, the cylinder
  table's normalisation).

Checks printed first: the sphere (k = 0.5 exactly), and a prolate and an oblate spheroid against
Lamb's closed forms (Lamb, Hydrodynamics, 6th ed., section 114; ``alpha_0, beta_0`` integrals),
which the test ``tests/test_revolution_added_mass.py`` re-evaluates with scipy.

    python benchmarks/added_mass_revolution_bem.py > benchmarks/results/added_mass_revolution_bem.txt
"""

import math
import sys

import capytaine as cpt
import numpy as np

RHO = 1.0
#: panels around the axis, and along the meridian per unit of the base radius (flank and caps)
N_THETA = 40
N_PER_RADIUS = 14
#: at most this many panels along the flank (the long cylinders of the cylinder check)
N_SIDE_MAX = 56
#: the table's grid: top/base radius ratio, and length over the base diameter
RATIOS = (0.0, 0.25, 0.5, 0.75, 1.0)
ASPECTS = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0)


def _graded(n):
    """n + 1 points on [0, 1], refined towards both ends (cosine spacing)."""
    return 0.5 * (1.0 - np.cos(np.linspace(0.0, math.pi, n + 1)))


def frustum_meridian(r_base, r_top, length):
    """The closed frustum's meridian (r, z): base centre (z = 0) -> base rim -> top rim -> top centre."""
    n_base = max(4, int(round(N_PER_RADIUS * r_base)))
    n_top = max(4, int(round(N_PER_RADIUS * r_top))) if r_top > 0.0 else 0
    n_side = min(N_SIDE_MAX, max(6, int(round(N_PER_RADIUS * math.hypot(length, r_base - r_top)))))
    pts = [(r_base * t, 0.0) for t in _graded(n_base)]
    pts += [(r_base + (r_top - r_base) * t, length * t) for t in _graded(n_side)[1:]]
    if r_top > 0.0:
        pts += [(r_top * (1.0 - t), length) for t in _graded(n_top)[1:]]
    return np.array(pts)


def spheroid_meridian(a_axial, b_radial, n=48):
    """A spheroid's meridian from the south pole to the north pole (axis z, semi-axes a along z)."""
    t = np.linspace(0.0, math.pi, n + 1)
    return np.column_stack([b_radial * np.sin(t), -a_axial * np.cos(t)])


def revolve(meridian, n_theta=N_THETA):
    """Mesh of the surface swept by the meridian polyline about z (normals outwards for a meridian
    running from the bottom of the axis to its top with r >= 0)."""
    r, z = meridian[:, 0], meridian[:, 1]
    phi = np.linspace(0.0, 2.0 * math.pi, n_theta, endpoint=False)
    verts = []
    index = {}
    for i in range(len(r)):
        for j in range(n_theta):
            if r[i] == 0.0 and j > 0:
                index[i, j] = index[i, 0]
                continue
            index[i, j] = len(verts)
            verts.append((r[i] * math.cos(phi[j]), r[i] * math.sin(phi[j]), z[i]))
    faces = []
    for i in range(len(r) - 1):
        for j in range(n_theta):
            jn = (j + 1) % n_theta
            a, b, c, d = index[i, j], index[i, jn], index[i + 1, jn], index[i + 1, j]
            if a == b:  # triangle at the axis
                faces.append((a, c, d, d))
            elif c == d:
                faces.append((a, b, c, c))
            else:
                faces.append((a, b, c, d))
    # a meridian from the bottom pole up with r >= 0 gives (a, b, c, d) anticlockwise seen from
    # outside on the flank: outward normals; checked by the sign of the mesh's volume below
    return cpt.Mesh(vertices=np.array(verts), faces=np.array(faces))


def strip_volume_moments(meridian):
    """V, x_v and strip theory's ``int r^2 (z - z_v)^2 dz`` / ... by the frusta of the polyline
    (caps contribute nothing: exact for the piecewise-linear r(z))."""
    r, z = meridian[:, 0], meridian[:, 1]
    m0 = m1 = m2 = 0.0
    gu = np.array([0.5 - 0.5 * math.sqrt(0.6), 0.5, 0.5 + 0.5 * math.sqrt(0.6)])
    gw = np.array([5.0, 8.0, 5.0]) / 18.0
    for i in range(len(r) - 1):
        h = z[i + 1] - z[i]
        if h == 0.0:
            continue
        for u, w in zip(gu, gw):
            zz = z[i] + h * u
            rr = r[i] + (r[i + 1] - r[i]) * u
            m0 += w * h * rr * rr
            m1 += w * h * rr * rr * zz
            m2 += w * h * rr * rr * zz * zz
    zv = m1 / m0
    return math.pi * m0, zv, math.pi * (m2 - m0 * zv * zv)


def coefficients(meridian, length):
    """(k_a, k_t, delta, k_r, volume check) of the body of the meridian (module docstring)."""
    volume, zv, strip_rot = strip_volume_moments(meridian)
    mesh = revolve(meridian)
    mesh_volume = mesh.volume
    if mesh_volume < 0.0:
        raise RuntimeError("inward normals")
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0.0, 0.0, zv)))
    solver = cpt.BEMSolver(method="direct")
    out = {}
    for dof in ("Heave", "Surge", "Pitch"):
        pb = cpt.RadiationProblem(
            body=body, free_surface=np.inf, water_depth=np.inf, omega=1.0, rho=RHO, radiating_dof=dof
        )
        res = solver.solve(pb, keep_details=False)
        out[dof] = res.added_masses
    m_axial = out["Heave"]["Heave"]
    m_t = out["Surge"]["Surge"]
    m_tr = 0.5 * (out["Surge"]["Pitch"] + out["Pitch"]["Surge"])
    m_rot = out["Pitch"]["Pitch"]
    zm_offset = m_tr / m_t
    k_r = (m_rot - m_tr * m_tr / m_t) / (RHO * strip_rot) if strip_rot > 0.0 else float("nan")
    return (
        m_axial / (RHO * volume),
        m_t / (RHO * volume),
        zm_offset / length,
        k_r,
        mesh_volume / volume - 1.0,
        mesh.nb_faces,
        (m_axial / RHO, m_t / RHO, m_tr / RHO, m_rot / RHO),
    )


def main(argv):
    quick = "--quick" in argv
    print(f"# capytaine {cpt.__version__}, direct method, N_THETA={N_THETA}, N_PER_RADIUS={N_PER_RADIUS}")
    print("# checks: body, k_axial, k_transverse (closed forms: tests/test_revolution_added_mass.py)")
    for name, a, b in (("sphere", 1.0, 1.0), ("prolate_2", 2.0, 1.0), ("oblate_0.45", 0.45, 1.0)):
        ka, kt, delta, _, dv, nf, _ = coefficients(spheroid_meridian(a, b), 2.0 * a)
        print(f"check {name} {ka:.5f} {kt:.5f} delta={delta:+.1e} dV={dv:+.1e} faces={nf}")
        sys.stdout.flush()
    if quick:
        return
    print(
        "# frustum: r_top/r_base, L/D_base, k_a, k_t, delta, k_r, dV (mesh volume / exact - 1), faces;"
        " then m_axial, m_transverse, m_coupling (surge-pitch about the centroid), m_pitch (about the"
        " centroid), of rho = 1, r_base = 1"
    )
    for q in RATIOS:
        for ld in ASPECTS:
            length = 2.0 * ld
            ka, kt, delta, kr, dv, nf, dims = coefficients(frustum_meridian(1.0, q, length), length)
            ma, mt, mc, mr = dims
            print(
                f"frustum {q:.2f} {ld:.2f} {ka:.5f} {kt:.5f} {delta:+.5f} {kr:.5f} {dv:+.1e} {nf}"
                f" {ma:.6f} {mt:.6f} {mc:+.6f} {mr:.6f}"
            )
            sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv[1:])
