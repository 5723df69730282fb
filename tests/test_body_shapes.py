"""Tests of the body's Python side (mineburial.kernels.mine.bodies.shapes) and of the compiled
protocol's ``reference_lengths``: the drop's shape gives the configuration, the ensembles and the
stepper their volume, mass properties, reference lengths and placement rule.

References: the volume, centroid and inertia tensor of the uniform solid cylinder by numerical
integration of their definitions over the body (scipy.integrate.tplquad in cylindrical
coordinates, not the closed forms under test); the lowest point by the rim's drop
``R sqrt(1 - a_z^2)`` below the lower end section's centre; the parameter rows and the
configuration's fields for the dimensions.
"""

import math

import numpy as np
import pytest
from numba import njit
from scipy import integrate

from mineburial.kernels.mine import bodies, dynamics, layout
from mineburial.kernels.mine.bodies import cylinder, shapes
from mineburial.kernels.mine.bodies.shapes import CYLINDER, DROP_SHAPE
from mineburial.systems.mine import config as cfg

L, D, CHI, M = 2.0, 0.6, 0.1, 700.0
DIMS = {"mine.length": L, "mine.diameter": D, "mine.com_offset": CHI}


def _over_body(f):
    """The integral of f(x, r, phi) over the solid cylinder of DIMS (x about the COM, along the
    axis; r, phi polar in the section), by scipy's tplquad with the Jacobian r."""
    value, _ = integrate.tplquad(
        lambda r, phi, x: f(x, r, phi) * r,
        -0.5 * L - CHI,
        0.5 * L - CHI,
        0.0,
        2.0 * math.pi,
        0.0,
        0.5 * D,
        epsabs=1e-13,
        epsrel=1e-11,
    )
    return value


def test_volume_and_centroid_are_the_integrals_over_the_body():
    volume = _over_body(lambda x, r, phi: 1.0)
    assert CYLINDER.volume(DIMS) == pytest.approx(volume, rel=1e-10)
    centroid = _over_body(lambda x, r, phi: x) / volume
    assert CYLINDER.centroid(DIMS) == pytest.approx(centroid, rel=1e-10)


def test_inertia_tensor_of_the_uniform_body_about_its_centroid_is_the_integral():
    rho = M / _over_body(lambda x, r, phi: 1.0)
    xc = CYLINDER.centroid(DIMS)
    j_axial = rho * _over_body(lambda x, r, phi: r * r)
    # about the transverse axis through the centroid (the y axis): x'^2 + z^2
    j_transverse = rho * _over_body(lambda x, r, phi: (x - xc) ** 2 + (r * math.sin(phi)) ** 2)
    # a product of inertia vanishes: the body is one of revolution
    j_xy = rho * _over_body(lambda x, r, phi: (x - xc) * r * math.cos(phi))
    tensor = CYLINDER.inertia_tensor(M, DIMS)
    assert tensor == pytest.approx(np.diag([j_axial, j_transverse, j_transverse]), rel=1e-10, abs=1e-9)
    assert abs(j_xy) < 1e-9
    assert CYLINDER.inertia(M, DIMS) == pytest.approx((j_axial, j_transverse), rel=1e-10)


def test_inertia_of_parameter_rows_is_that_of_each_row():
    rows = np.zeros((3, layout.N_PARAMS))
    rows[:, layout.P_LENGTH] = [1.0, 2.0, 3.8]
    rows[:, layout.P_DIAMETER] = [0.3, 0.6, 0.53]
    rows[:, layout.P_CHI] = [0.0, 0.1, -0.2]
    masses = np.array([100.0, 700.0, 1000.0])
    j1, j2 = CYLINDER.inertia(masses, CYLINDER.dims_of_params(rows))
    for i in range(3):
        r = 0.5 * rows[i, layout.P_DIAMETER]
        assert j1[i] == pytest.approx(masses[i] * r * r / 2.0, rel=1e-15)
        assert j2[i] == pytest.approx(
            masses[i] * (3.0 * r * r + rows[i, layout.P_LENGTH] ** 2) / 12.0, rel=1e-15
        )


def test_the_configurations_mine_takes_its_mass_properties_from_the_drops_shape():
    mine = cfg.Mine(length=L, diameter=D, mass=M, com_offset=CHI)
    assert mine.volume == pytest.approx(math.pi * (0.5 * D) ** 2 * L, rel=1e-15)
    assert mine.density == pytest.approx(M / (math.pi * (0.5 * D) ** 2 * L), rel=1e-15)
    r = 0.5 * D
    assert (mine.inertia_axial, mine.inertia_transverse) == pytest.approx(
        (M * r * r / 2.0, M * (3.0 * r * r + L * L) / 12.0), rel=1e-15
    )


@pytest.mark.parametrize("a_z", [-1.0, -0.6, 0.0, 0.35, 1.0])
def test_lowest_point_is_the_lower_end_sections_rim(a_z):
    z = 3.0
    xa, xb = -0.5 * L - CHI, 0.5 * L - CHI
    expected = z + min(a_z * xa, a_z * xb) - 0.5 * D * math.sqrt(1.0 - a_z * a_z)
    assert float(CYLINDER.lowest_point(DIMS, a_z, z)) == pytest.approx(expected, rel=1e-13, abs=1e-15)
    # arrays broadcast: one value per drop
    got = CYLINDER.lowest_point({**DIMS, "mine.length": np.array([L, L])}, a_z, np.array([z, z + 1.0]))
    assert got == pytest.approx([expected, expected + 1.0], rel=1e-13, abs=1e-15)


def test_the_placement_rule_refuses_a_mine_released_into_the_seabed():
    # a horizontal mine of diameter 0.6 with its COM 0.2 m above a 10 m deep seabed reaches 0.1 m in
    values = {
        **DIMS,
        "release.z": -9.8,
        "environment.water_depth": 10.0,
        "release.embedded": False,
        **dict(zip(cfg._Q, (1.0, 0.0, 0.0, 0.0))),
    }
    assert not cfg._starts_above_seabed(values)
    assert "0.1 m inside the seabed" in cfg._inside_seabed_message(values)
    assert cfg._starts_above_seabed({**values, "release.z": -9.7 + 1e-9})


def test_the_drops_shape_names_the_kernels_body():
    assert DROP_SHAPE is CYLINDER and shapes.DEFAULT_SHAPE is CYLINDER
    assert dynamics._default_body is cylinder.from_params
    assert DROP_SHAPE.kernel() is cylinder
    # issue 36: mine.shape chooses among the registered shapes; the placement rule reads every field
    assert tuple(shapes.SHAPES) == layout.MINE_SHAPES
    assert set(cfg._BODY) == {"mine.shape", *(f for s in shapes.SHAPES.values() for f in s.fields)}
    frustum = shapes.FRUSTUM.kernel()
    assert bodies.SHAPES[frustum.Frustum] is frustum
    assert shapes.FRUSTUM.marker() is frustum.PROTOTYPE and CYLINDER.marker() is None


def test_compiled_reference_lengths_and_volume_agree_with_the_python_side_bit_for_bit():
    probe = njit(cache=False)(
        lambda p: (bodies.reference_lengths(dynamics.drop_body(p)), bodies.volume(dynamics.drop_body(p)))
    )
    rng = np.random.default_rng(7)
    rows = np.zeros((50, layout.N_PARAMS))
    rows[:, layout.P_LENGTH] = rng.uniform(0.5, 4.0, 50)
    rows[:, layout.P_DIAMETER] = rng.uniform(0.1, 1.2, 50)
    rows[:, layout.P_CHI] = rng.uniform(-0.2, 0.2, 50)
    for p in rows:
        (diameter, length), (volume, centroid) = probe(p)
        dims = DROP_SHAPE.dims_of_params(p)
        # the sediment law's width is the parameter's diameter exactly (halved and doubled)
        assert (diameter, length) == (p[layout.P_DIAMETER], p[layout.P_LENGTH])
        assert (diameter, length) == DROP_SHAPE.reference_lengths(dims)
        assert volume == pytest.approx(DROP_SHAPE.volume(dims), rel=4e-16)
        assert centroid == DROP_SHAPE.centroid(dims)


def test_the_shapes_module_imports_no_shape_kernel():
    # the configuration imports it: a shape's kernel module would bring the sediment kernels
    import ast
    import inspect

    tree = ast.parse(inspect.getsource(shapes))
    imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert not any("sediment" in m or m.endswith(".cylinder") for m in imported), imported


def test_the_shapes_rule_keeps_the_com_inside_the_body():
    rule = next(r for r in cfg.RULES if r in DROP_SHAPE.rules)
    lengths = np.array([2.0, 2.0, 2.0, 2.0])
    offsets = np.array([0.0, 0.99, -1.0, 1.2])  # inside, inside, on the end, beyond
    assert rule.holds({"mine.length": lengths, "mine.com_offset": offsets}).tolist() == [
        True,
        True,
        False,
        False,
    ]
    with pytest.raises(cfg.ScenarioError, match="mine.com_offset"):
        cfg.Mine(length=2.0, diameter=0.5, mass=500.0, com_offset=1.0)


def test_importing_the_configuration_loads_no_shape_kernel_nor_sediment_kernel():
    import subprocess
    import sys

    code = (
        "import sys, mineburial.systems.mine.config; print(sorted(m for m in sys.modules "
        "if m.startswith('mineburial.kernels.mine.sediment') or m.endswith('bodies.cylinder')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


#: a body of revolution whose profile the test gives: a frustum of length L, tail diameter d,
#: nose diameter d_nose, its COM chi behind the middle (a field that no scenario declares yet)
FRUSTUM_SHAPE = shapes.ProfileShape(
    "frustum",
    ("mine.length", "mine.diameter", "test.nose_diameter", "mine.com_offset"),
    ("mine.length", "mine.diameter", "test.nose_diameter"),
    lambda d: (
        (-0.5 * d["mine.length"] - d["mine.com_offset"], 0.5 * d["mine.length"] - d["mine.com_offset"]),
        (0.5 * d["mine.diameter"], 0.5 * d["test.nose_diameter"]),
    ),
)


def test_a_profile_of_one_radius_has_the_cylinders_python_side():
    dims = {**DIMS, "test.nose_diameter": D}
    assert FRUSTUM_SHAPE.volume(dims) == pytest.approx(CYLINDER.volume(DIMS), rel=1e-14)
    assert FRUSTUM_SHAPE.centroid(dims) == pytest.approx(CYLINDER.centroid(DIMS), rel=1e-14)
    assert FRUSTUM_SHAPE.inertia(M, dims) == pytest.approx(CYLINDER.inertia(M, DIMS), rel=1e-14)
    assert FRUSTUM_SHAPE.reference_lengths(dims) == pytest.approx((D, L), rel=1e-15)
    for a_z in (-0.8, 0.0, 0.5, 1.0):
        assert float(FRUSTUM_SHAPE.lowest_point(dims, a_z, 2.0)) == pytest.approx(
            float(CYLINDER.lowest_point(DIMS, a_z, 2.0)), abs=1e-15
        )


def test_a_cones_python_side_is_the_solid_cones_closed_forms():
    # a solid cone (nose diameter 0) of base radius R, height h: V = pi R^2 h / 3, centroid h/4 above the
    # base, J_axial = 3 m R^2 / 10, J_transverse = 3 m R^2 / 20 + 3 m h^2 / 80 about the centroid
    h, r, chi = 1.2, 0.45, 0.05
    dims = {"mine.length": h, "mine.diameter": 2.0 * r, "test.nose_diameter": 0.0, "mine.com_offset": chi}
    assert FRUSTUM_SHAPE.volume(dims) == pytest.approx(math.pi * r * r * h / 3.0, rel=1e-14)
    assert FRUSTUM_SHAPE.centroid(dims) == pytest.approx(-0.5 * h - chi + 0.25 * h, rel=1e-14)
    j1, j2 = FRUSTUM_SHAPE.inertia(M, dims)
    assert (j1, j2) == pytest.approx((0.3 * M * r * r, 0.15 * M * r * r + 3.0 * M * h * h / 80.0), rel=1e-14)
    # on its base (axis up): the base's rim and centre are lowest; nose down: the tip is
    assert float(FRUSTUM_SHAPE.lowest_point(dims, 1.0, 0.0)) == pytest.approx(-0.5 * h - chi, rel=1e-14)
    assert float(FRUSTUM_SHAPE.lowest_point(dims, -1.0, 0.0)) == pytest.approx(-(0.5 * h - chi), rel=1e-14)


def test_a_profiles_python_side_takes_one_value_per_drop():
    lengths = np.array([1.0, 1.5, 2.0])
    dims = {"mine.length": lengths, "mine.diameter": 0.6, "test.nose_diameter": 0.3, "mine.com_offset": 0.0}
    volumes = FRUSTUM_SHAPE.volume(dims)
    r0, r1 = 0.3, 0.15
    assert volumes == pytest.approx(math.pi * lengths * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0, rel=1e-14)
    j1, j2 = FRUSTUM_SHAPE.inertia(np.array([100.0, 200.0, 300.0]), dims)
    assert j1.shape == j2.shape == (3,)
    j1_one, _ = FRUSTUM_SHAPE.inertia(
        200.0, {k: (v[1] if k == "mine.length" else v) for k, v in dims.items()}
    )
    assert j1[1] == pytest.approx(j1_one, rel=1e-15)
    assert FRUSTUM_SHAPE.lowest_point(dims, 0.0, np.zeros(3)) == pytest.approx([-0.3, -0.3, -0.3], rel=1e-15)
