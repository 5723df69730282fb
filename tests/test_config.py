"""Scenario configuration: loading, validation messages, round trips, orientation helpers,
packing into the kernel layout."""

import dataclasses
import json
import math
import pathlib

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mineburial.errors import ScenarioError
from mineburial.kernels.mine import layout
from mineburial.kernels.rotation import euler_angles, normalize_quaternion, rotation_matrix
from mineburial.systems.mine import config
from mineburial.systems.mine.config import (
    FIELDS,
    Current,
    Numerics,
    Release,
    Scenario,
    Sediment,
    check_params,
    check_range,
    explain_params,
    quaternion_from_angles,
    tomllib,
)
from mineburial.systems.mine.sediment_profiles import catalogue_profile, pack_banks

G_CM2 = 1e-7  # kg m2 per g cm2


def base() -> dict:
    """A minimal valid scenario dict (fresh copy)."""
    return {
        "mine": {"length": 2.0, "diameter": 0.5, "mass": 700.0},
        "release": {"position": [0.0, 0.0, 5.0], "pitch_deg": 30.0},
        "environment": {"water_depth": 30.0},
        "sediment": {"class": "soft_clay"},
    }


def full() -> dict:
    """A scenario that sets every field to a distinct, non-default value."""
    return {
        "description": "every field set",
        "mine": {
            "name": "m1",
            "length": 2.1,
            "diameter": 0.52,
            "mass": 640.0,
            "com_offset": -0.07,
            "inertia_axial": 21.0,
            "inertia_transverse": 230.0,
        },
        "release": {
            "position": [1.5, -2.5, 12.0],
            "velocity": [3.1, -0.4, -7.2],
            "roll_deg": 12.0,
            "pitch_deg": 37.0,
            "heading_deg": -115.0,
            "angular_velocity": [0.11, -0.22, 0.33],
        },
        "environment": {
            "gravity": 9.806,
            "air_density": 1.2,
            "air_viscosity": 1.6e-5,
            "water_density": 1027.0,
            "water_viscosity": 1.2e-6,
            "water_depth": 41.0,
            "current": {"kind": "power_law", "surface_velocity": [0.6, -0.2], "exponent": 0.2},
        },
        "sediment": {
            "density": 1550.0,
            "density_gradient": 45.0,
            "strength": 2500.0,
            "strength_gradient": 1300.0,
            "resistance": "friction",
            "rate_law": "none",
            "impact_factor": 8.0,
            "rest_speed": 0.05,
            "rate_coefficient": 0.15,
            "reference_rate": 1e-5,
            "friction": 0.45,
            "bearing_factor": 9.0,
            "pore_pressure": True,
            "rupture_length": 0.2,
            "permeability": 2e-4,
            "void_ratio": 1.5,
            "bearing_depth_factor": 0.85,
            "inertial_drag": 0.7,
        },
        "numerics": {
            "model": "impact35",
            "integrator": "rk4",
            "dt": 5e-4,
            "t_max": 30.0,
            "t_max_fall": 120.0,
            "rest_speed": 2e-3,
            "rest_spin": 3e-2,
            "drag": False,
            "munk_factor": 0.3,
            "crossflow_drag_factor": 1.4,
            "crossflow_munk_fraction": 0.3,
            "added_mass_factor": 1.1,
        },
    }


# ---------------------------------------------------------------------------
# examples
# ---------------------------------------------------------------------------
def test_examples_are_listed_and_load():
    names = config.example_names()
    for required in ("exp1_case92", "exp1_case93", "exp2_barrel", "default_mine"):
        assert required in names
    for name in names:
        s = config.load_example(name)
        assert isinstance(s, Scenario) and s.description
        p, sed, cur = s.to_params()
        assert np.all(np.isfinite(p)) and check_params(p, len(sed), len(cur)).all()
    with pytest.raises(ScenarioError, match=r"did you mean 'exp2_barrel'"):
        config.example_path("exp2_barel")


def test_exp1_examples_reproduce_seed_000_table_2():
    # Seed 000 Table 2 / eqs. (92a), (93a): masses, lengths, volumes, densities, J in g cm^2
    for name, m, L, vol_cm3, rho_gcm3, chi, j1, j2 in (
        ("exp1_case92", 322.5, 15.20, 191.01, 1.69, 0.74, 330.5, 5783.0),
        ("exp1_case93", 254.2, 12.10, 152.05, 1.67, -1.00, 271.3, 3312.6),
    ):
        mine = config.load_example(name).mine
        assert mine.mass == pytest.approx(m * 1e-3, rel=1e-12)
        assert mine.length == pytest.approx(L * 1e-2, rel=1e-12)
        assert mine.com_offset == pytest.approx(chi * 1e-2, rel=1e-12)
        assert mine.inertia_axial == pytest.approx(j1 * G_CM2, rel=1e-12)
        assert mine.inertia_transverse == pytest.approx(j2 * G_CM2, rel=1e-12)
        assert mine.volume == pytest.approx(vol_cm3 * 1e-6, rel=5e-4)  # R = 2.0 cm
        assert mine.density == pytest.approx(rho_gcm3 * 1e3, abs=5.0)  # 3 printed digits
    s92 = config.load_example("exp1_case92")
    assert s92.release.velocity == (0.0, -1.55, -2.52)
    assert s92.release.angles_deg == (0.0, 60.0, -95.0)
    assert s92.release.angular_velocity == (0.0, 0.49, 0.29)
    assert s92.environment.water_density == 998.0
    s93 = config.load_example("exp1_case93")
    assert s93.release.angles_deg == (0.0, 24.0, -96.0)
    assert s93.release.angular_velocity == (0.0, -5.08, 0.15)


def test_exp2_barrel_example():
    s = config.load_example("exp2_barrel")
    assert s.mine.density == pytest.approx(1800.0, rel=1e-3)  # density ratio ~1.8
    assert s.release.velocity == (0.0, 0.0, 0.0)  # eq. (90): V_in = 0
    assert s.release.pitch_deg == 0.0  # "released horizontally"
    assert s.release.position[2] == pytest.approx(s.mine.radius)  # touching the surface
    assert s.environment.water_depth == 13.0
    prof = s.sediment.profile
    # strengths inside the fall-cone range of Table 4 (0.0063-25 kPa)
    assert prof.strength.min() >= 6.3 and prof.strength.max() <= 25e3
    # rising over the top 6-9 cm, then levelling off
    top = prof.depth <= 0.09
    assert np.all(np.diff(prof.density[top]) > 0) and np.all(np.diff(prof.strength[top]) > 0)
    below = prof.depth >= 0.10
    assert np.ptp(prof.density[below]) < 0.1 * np.ptp(prof.density)


# ---------------------------------------------------------------------------
# round trips and defaults
# ---------------------------------------------------------------------------
def _scenarios():
    quat = base()
    del quat["release"]["pitch_deg"]
    quat["release"]["quaternion"] = [0.9, 0.1, 0.3, -0.2]
    table = base()
    table["environment"]["current"] = {
        "kind": "table",
        "depth": [0.0, 10.0, 30.0],
        "u": [0.5, 0.3, 0.0],
        "v": [0.0, 0.1, 0.0],
    }
    table["sediment"] = {
        "profile": {"depth": [0.0, 0.05, 0.2], "density": [1300, 1500, 1600], "strength": [100, 800, 1500]}
    }
    uniform = base()
    uniform["environment"]["current"] = {"kind": "uniform", "velocity": [0.2, -0.1]}
    out = [full(), base(), quat, table, uniform]
    out += [config.load_example(n).to_dict() for n in config.example_names()]
    return out


@pytest.mark.parametrize("d", _scenarios())
def test_round_trip_dict_json_toml(d):
    s = Scenario.from_dict(d)
    assert Scenario.from_dict(s.to_dict()) == s
    assert Scenario.from_dict(json.loads(s.to_json())) == s
    assert Scenario.from_dict(tomllib.loads(s.to_toml())) == s
    # to_dict is fully resolved: no None anywhere (TOML has no null)
    assert "null" not in s.to_json()


def test_defaults_are_filled():
    s = Scenario.from_dict(base())
    m = s.mine
    r = 0.25
    assert m.inertia_axial == pytest.approx(700.0 * r * r / 2)
    assert m.inertia_transverse == pytest.approx(700.0 * (3 * r * r + 4.0) / 12)
    assert s.environment.gravity == 9.81 and s.environment.water_density == 1025.0
    assert s.environment.current.kind == "none"
    assert s.numerics.dt == 1e-3 and s.numerics.t_max == 60.0 and s.numerics.drag is True
    assert s.numerics.t_max_fall == 600.0
    assert s.sediment.impact_factor == 10.0 and s.sediment.rest_speed == 0.04  # seed 000 (72)
    assert s.sediment.pore_pressure is False
    # catalogue class expanded into its values
    d = s.to_dict()
    assert "class" not in d["sediment"] and d["sediment"]["profile"]["name"] == "soft_clay"
    assert s.sediment.profile == catalogue_profile("soft_clay")


def test_model_dependent_defaults():
    s = Scenario.from_dict(base())
    assert (s.sediment.resistance, s.sediment.rate_law, s.numerics.integrator) == (
        "bearing",
        "semilog",
        "dopri5_ros34pw2",
    )
    d = base()
    d["numerics"] = {"model": "impact35"}
    s = Scenario.from_dict(d)
    assert (s.sediment.resistance, s.sediment.rate_law, s.numerics.integrator) == (
        "delta",
        "impact35",
        "dopri5",
    )
    assert (s.numerics.rtol, s.numerics.atol) == (1e-5, 1e-6)
    mb = Scenario.from_dict(base()).numerics
    assert (mb.rtol, mb.atol) == (3e-4, 3e-5)
    d["sediment"]["resistance"] = "bearing"  # explicit choices win
    d["numerics"]["integrator"] = "rk4"
    s = Scenario.from_dict(d)
    assert (s.sediment.resistance, s.numerics.integrator) == ("bearing", "rk4")


def test_replace_revalidates_and_none_recomputes_inertia():
    s = Scenario.from_dict(base())
    with pytest.raises(ScenarioError, match=r"mine\.length = -1\.0 m"):
        dataclasses.replace(s.mine, length=-1.0)
    heavier = dataclasses.replace(s.mine, mass=1400.0, inertia_axial=None, inertia_transverse=None)
    assert heavier.inertia_axial == pytest.approx(2 * s.mine.inertia_axial)
    s2 = dataclasses.replace(s, mine=heavier)
    assert s2.mine.mass == 1400.0 and s2 != s
    s3 = dataclasses.replace(s, release=dataclasses.replace(s.release, pitch_deg=45.0))
    assert s3.release.pitch_deg == 45.0


def test_sediment_file_relative_to_scenario(tmp_path):
    (tmp_path / "cores").mkdir()
    (tmp_path / "cores" / "c1.csv").write_text(
        "depth_m,density_kg_m3,strength_pa\n0,1400,200\n0.1,1600,1500\n"
    )
    d = base()
    d["sediment"] = {"file": "cores/c1.csv", "friction": 0.4}
    (tmp_path / "s.toml").write_text(config.dumps_toml(d))
    s = Scenario.from_toml(tmp_path / "s.toml")
    np.testing.assert_array_equal(s.sediment.profile.strength, [200.0, 1500.0])
    assert s.sediment.friction == 0.4
    # the output dict carries the values, not the file: it reads back without the file
    (tmp_path / "cores" / "c1.csv").unlink()
    assert Scenario.from_dict(s.to_dict()) == s


# ---------------------------------------------------------------------------
# validation messages
# ---------------------------------------------------------------------------
def _set(d, path, value):
    keys = path.split(".")
    node = d
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    node[keys[-1]] = value


BAD = [
    ("mine.length", -1.0, r"mine\.length = -1\.0 m is outside the allowed range \(0, 50\] m"),
    ("mine.diameter", 0.0, r"mine\.diameter = 0\.0 m is outside the allowed range \(0, 10\] m"),
    ("mine.mass", 2e5, r"mine\.mass = 200000\.0 kg is outside the allowed range \(0, 100000\] kg"),
    (
        "mine.com_offset",
        1.0,
        r"mine\.com_offset = 1\.0 m is outside the allowed range "
        r"\(-1, 1\) m \(\|chi\| < length/2",
    ),
    (
        "mine.inertia_axial",
        1e3,
        r"mine\.inertia_axial = 1000\.0 kg m2 is outside the allowed "
        r"range \(0, 4.*\] kg m2 \(J1 <= 2 J2",
    ),
    ("mine.inertia_transverse", -3.0, r"mine\.inertia_transverse = -3\.0 kg m2 is outside"),
    ("mine.length", "2", r"mine\.length = '2' must be a number \(m\)"),
    ("mine.mass", True, r"mine\.mass = True must be a number"),
    ("mine.length", float("nan"), r"mine\.length = nan m is outside"),
    (
        "release.position",
        [0.0, 0.0, -40.0],
        r"release\.position\[2\] \(release\.z\) = -40\.0 m is outside the allowed range "
        r"\(-30, 20000\] m \(the COM must start above the seabed",
    ),
    ("release.position", [0.0, 0.0], r"release\.position = \[0\.0, 0\.0\] must be a list of 3"),
    (
        "release.velocity",
        [0.0, 0.0, 600.0],
        r"release\.velocity\[2\] \(release\.w\) = 600\.0 m s-1 is outside the allowed range "
        r"\[-500, 500\] m s-1",
    ),
    (
        "release.pitch_deg",
        95.0,
        r"release\.pitch_deg = 95\.0 deg is outside the allowed range "
        r"\[-90, 90\] deg",
    ),
    (
        "release.angular_velocity",
        [0, 0, 2000],
        r"release\.angular_velocity\[2\] \(release\.omega3\) = 2000\.0 rad s-1",
    ),
    ("release.quaternion", [1.0, 0, 0, 0], r"either the angles .* or quaternion, not both"),
    (
        "environment.water_depth",
        0.0,
        r"environment\.water_depth = 0\.0 m is outside the "
        r"allowed range \(0, 11000\] m",
    ),
    ("environment.water_density", 2000.0, r"environment\.water_density = 2000\.0 kg m-3"),
    ("environment.gravity", -9.81, r"environment\.gravity = -9\.81 m s-2 is outside"),
    (
        "environment.current",
        {"kind": "uniform", "velocity": [20.0, 0.0]},
        r"environment\.current\.velocity\[0\] \(current\.u\) = 20\.0 m s-1 is outside the "
        r"allowed range \[-10, 10\] m s-1",
    ),
    (
        "environment.current",
        {"kind": "power_law", "surface_velocity": [1.0, 0.0], "exponent": 0.0},
        r"environment\.current\.exponent \(current\.exponent\) = 0\.0 is outside the allowed "
        r"range \(0, 1\]$",
    ),
    (
        "environment.current",
        {"kind": "power_law", "velocity": [1.0, 0.0]},
        r"key 'velocity' is not used by kind 'power_law'",
    ),
    (
        "environment.current",
        {"kind": "table", "depth": [0.0, 5.0], "u": [0.1], "v": [0, 0]},
        r"same non-zero length",
    ),
    (
        "environment.current",
        {"kind": "table", "depth": [5.0, 1.0], "u": [0, 0], "v": [0, 0]},
        r"strictly increasing",
    ),
    (
        "sediment.friction",
        -0.1,
        r"sediment\.friction = -0\.1 is outside the allowed range "
        r"\[0, 5\]$",
    ),
    (
        "sediment.impact_factor",
        0.5,
        r"sediment\.impact_factor = 0\.5 is outside the allowed "
        r"range \[1, 100\]",
    ),
    (
        "sediment.rest_speed",
        0.0,
        r"sediment\.rest_speed = 0\.0 m s-1 is outside the allowed "
        r"range \(0, 10\] m s-1",
    ),
    ("sediment.permeability", 5.0, r"sediment\.permeability = 5\.0 m s-1"),
    ("sediment.pore_pressure", 1, r"sediment\.pore_pressure = 1 must be true or false"),
    ("sediment.density", 1500.0, r"give exactly one profile: .*\(got class, density/strength\)"),
    ("numerics.dt", 0.0, r"numerics\.dt = 0\.0 s is outside the allowed range \(0, 1\] s"),
    (
        "numerics.dt",
        0.5,
        r"numerics\.dt = 0\.5 s is outside the allowed range \(0, 0\.1\] s "
        r"\(dt <= numerics\.t_max\)",
    ),
    (
        "numerics.dt",
        0.4,
        r"numerics\.dt = 0\.4 s is outside the allowed range \(0, 0\.2\] s "
        r"\(dt <= numerics\.t_max_fall\)",
    ),
    (
        "numerics.t_max_fall",
        0.0,
        r"numerics\.t_max_fall = 0\.0 s is outside the allowed range \(0, 1e\+06\] s",
    ),
    ("numerics.rest_spin", -1.0, r"numerics\.rest_spin = -1\.0 rad s-1"),
    ("numerics.drag", "yes", r"numerics\.drag = 'yes' must be true or false"),
]


@pytest.mark.parametrize("path, value, match", BAD, ids=[f"{b[0]}={b[1]!r}" for b in BAD])
def test_bad_values_name_path_value_and_range(path, value, match):
    d = base()
    d["mine"]["length"] = 2.0
    if path == "numerics.dt" and value == 0.5:
        d["numerics"] = {"t_max": 0.1}
    if path == "numerics.dt" and value == 0.4:
        d["numerics"] = {"t_max_fall": 0.2}
    _set(d, path, value)
    with pytest.raises(ScenarioError, match=match):
        Scenario.from_dict(d)


def test_linear_sediment_errors():
    with pytest.raises(ScenarioError, match=r"either a tabulated profile .* or a linear one"):
        Sediment(profile=catalogue_profile("sand"), strength=1e3)
    d = base()
    d["sediment"] = {"density": 1500.0, "strength": 1e3, "strength_gradient": -5.0}
    with pytest.raises(
        ScenarioError,
        match=r"sediment\.strength_gradient = -5\.0 Pa m-1 is "
        r"outside the allowed range \[0, 1e\+06\] Pa m-1",
    ):
        Scenario.from_dict(d)
    d["sediment"] = {"density": 1500.0}
    with pytest.raises(ScenarioError, match=r"sediment\.strength is required"):
        Scenario.from_dict(d)
    d["sediment"] = {"friction": 0.3}
    with pytest.raises(
        ScenarioError,
        match=r"give exactly one profile: class = one of .*"
        r"\(got none\)",
    ):
        Scenario.from_dict(d)
    d["sediment"] = {"class": "sand", "file": "x.csv"}
    with pytest.raises(ScenarioError, match=r"\(got class, file\)"):
        Scenario.from_dict(d)
    d["sediment"] = {
        "profile": {"depth": [0.0, 0.1], "density": [1400, 1500], "strength": [0, 1], "colour": "grey"}
    }
    with pytest.raises(ScenarioError, match=r"sediment\.profile: unknown key 'colour'"):
        Scenario.from_dict(d)


@pytest.mark.parametrize(
    "mutate, match",
    [
        (
            lambda d: d["mine"].update(lenght=2.0),
            r"\[mine\]: unknown key 'lenght': did you mean 'length'\? allowed: com_offset, diameter",
        ),
        (
            lambda d: d.update(enviroment={}),
            r"unknown section 'enviroment': did you mean 'environment'\? allowed: description",
        ),
        (
            lambda d: d["sediment"].update({"class": "sof_clay"}),
            r"unknown sediment class 'sof_clay': did you mean 'soft_clay'\?",
        ),
        (
            lambda d: d["sediment"].update(resistance="baring"),
            r"sediment\.resistance: unknown name 'baring': did you mean 'bearing'\? allowed: "
            r"bearing, delta, friction",
        ),
        (
            lambda d: d["sediment"].update(rate_law="semi_log"),
            r"sediment\.rate_law: unknown name 'semi_log': did you mean 'semilog'\?",
        ),
        (
            lambda d: d.update(numerics={"integrater": "rk4"}),
            r"\[numerics\]: unknown key 'integrater': did you mean 'integrator'\?",
        ),
        (
            lambda d: d.update(numerics={"model": "impact36"}),
            r"numerics\.model: unknown name 'impact36': did you mean 'impact35'\?",
        ),
        (
            lambda d: d["environment"].update(current={"kind": "powerlaw"}),
            r"environment\.current\.kind: unknown name 'powerlaw': did you mean 'power_law'\?",
        ),
        (
            lambda d: d["environment"].update(current={"kind": "uniform", "velocty": [0, 0]}),
            r"unknown key 'velocty': did you mean 'velocity'\?",
        ),
        (lambda d: d["release"].update(pich_deg=3.0), r"unknown key 'pich_deg': did you mean 'pitch_deg'\?"),
        (lambda d: d["mine"].pop("mass"), r"mine\.mass \[kg\] is required"),
        (lambda d: d.pop("sediment"), r"\[sediment\] section is required"),
    ],
)
def test_unknown_names_suggest_nearest(mutate, match):
    d = base()
    mutate(d)
    with pytest.raises(ScenarioError, match=match):
        Scenario.from_dict(d)


def test_toml_file_errors(tmp_path):
    with pytest.raises(ScenarioError, match="cannot read scenario file"):
        Scenario.from_toml(tmp_path / "nope.toml")
    (tmp_path / "bad.toml").write_text("[mine\nlength = 1")
    with pytest.raises(ScenarioError, match="not valid TOML"):
        Scenario.from_toml(tmp_path / "bad.toml")


# ---------------------------------------------------------------------------
# orientation: config.quaternion_from_angles and its inverse, the kernels' euler_angles
# ---------------------------------------------------------------------------
def rotation_matrix_from_quaternion(q):
    """The kernel's rotation matrix of each quaternion of q (..., 4), as (..., 3, 3)."""
    q = np.asarray(q, dtype=np.float64)
    rows = [rotation_matrix(*normalize_quaternion(*row)) for row in q.reshape(-1, 4)]
    return np.array(rows).reshape(q.shape[:-1] + (3, 3))


def angles_from_quaternion(q):
    """The kernel's (psi1, psi2, psi3) of each quaternion of q (..., 4)."""
    q = np.asarray(q, dtype=np.float64)
    out = np.array([euler_angles(*normalize_quaternion(*row)) for row in q.reshape(-1, 4)])
    return tuple(out[:, k].reshape(q.shape[:-1]) for k in range(3))


def test_quaternion_matches_scipy_zyx_and_seed_000_main_axis():
    rng = np.random.default_rng(1)
    n = 500
    psi1 = rng.uniform(-np.pi, np.pi, n)
    psi2 = rng.uniform(-np.pi / 2, np.pi / 2, n)
    psi3 = rng.uniform(-np.pi, np.pi, n)
    q = quaternion_from_angles(psi1, psi2, psi3)
    assert q.shape == (n, 4)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, rtol=0, atol=1e-15)
    # independent reference: intrinsic Z-Y-X rotation R = Rz(psi3) Ry(psi2) Rx(psi1)
    ref = Rotation.from_euler("ZYX", np.stack([psi3, psi2, psi1], axis=1))
    np.testing.assert_allclose(rotation_matrix_from_quaternion(q), ref.as_matrix(), atol=1e-14)
    xyzw = ref.as_quat()
    ref_q = np.concatenate([xyzw[:, 3:], xyzw[:, :3]], axis=1)
    sign = np.sign(np.sum(ref_q * q, axis=1))[:, None]
    np.testing.assert_allclose(q, sign * ref_q, atol=1e-15)
    # seed 000 eq. (4): i_M = (cos psi3 cos psi2, sin psi3 cos psi2, -sin psi2)
    i_m = np.stack([np.cos(psi3) * np.cos(psi2), np.sin(psi3) * np.cos(psi2), -np.sin(psi2)], 1)
    np.testing.assert_allclose(ref.apply([1.0, 0.0, 0.0]), i_m, atol=1e-14)
    np.testing.assert_allclose(rotation_matrix_from_quaternion(q)[:, :, 0], i_m, atol=1e-14)


def test_angles_round_trip_and_gimbal_lock():
    rng = np.random.default_rng(2)
    n = 500
    psi = np.stack([rng.uniform(-3.1, 3.1, n), rng.uniform(-1.55, 1.55, n), rng.uniform(-3.1, 3.1, n)])
    back = np.array(angles_from_quaternion(quaternion_from_angles(*psi)))
    np.testing.assert_allclose(back, psi, atol=1e-12)
    # the sign of the quaternion does not matter
    back2 = np.array(angles_from_quaternion(-quaternion_from_angles(*psi)))
    np.testing.assert_allclose(back2, psi, atol=1e-12)
    # nose vertical: psi1 = 0 by convention and the rotation is preserved
    for pitch in (np.pi / 2, -np.pi / 2):
        q = quaternion_from_angles(0.7, pitch, -0.4)
        a1, a2, a3 = angles_from_quaternion(q)
        assert a1 == 0.0 and a2 == pytest.approx(pitch, abs=1e-7)
        ref = Rotation.from_euler("ZYX", [-0.4, pitch, 0.7]).as_matrix()
        np.testing.assert_allclose(
            rotation_matrix_from_quaternion(quaternion_from_angles(a1, a2, a3)), ref, atol=1e-7
        )


def test_release_quaternion_is_normalised_and_angles_derived():
    r = Release(quaternion=(2.0, 0.0, 0.0, 0.0))
    assert r.quaternion == (1.0, 0.0, 0.0, 0.0)
    r = Release(quaternion=[0.9, 0.1, 0.3, -0.2])
    assert np.linalg.norm(r.q) == pytest.approx(1.0, abs=1e-15)
    # normalisation is idempotent, so round trips are exact
    assert Release(quaternion=r.quaternion) == r
    roll, pitch, heading = r.angles_deg
    ref = Rotation.from_quat([0.1, 0.3, -0.2, 0.9]).as_euler("ZYX", degrees=True)
    np.testing.assert_allclose([heading, pitch, roll], ref, atol=1e-12)
    with pytest.raises(ScenarioError, match=r"norm 0 ~ 0"):
        Release(quaternion=(0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ScenarioError, match=r"release\.quaternion = .* must be a list of 4"):
        Release(quaternion=(1.0, 0.0, 0.0))
    # angles mode: missing angles are 0; the quaternion of pure pitch is (cos, 0, sin, 0)/2
    r = Release(pitch_deg=90.0)
    assert r.angles_deg == (0.0, 90.0, 0.0)
    np.testing.assert_allclose(r.q, [math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0], atol=1e-16)


# ---------------------------------------------------------------------------
# packing for the kernels
# ---------------------------------------------------------------------------
def test_to_params_puts_each_value_in_its_named_slot():
    d = full()
    s = Scenario.from_dict(d)
    p, sed_bank, cur_bank = s.to_params()
    assert p.shape == (layout.N_PARAMS,) and p.dtype == np.float64 and np.all(np.isfinite(p))
    assert sed_bank.shape == (0, 3, 1) and cur_bank.shape == (0, 3, 1)
    idx = layout.INDEX
    m, r, e, sd, nm = d["mine"], d["release"], d["environment"], d["sediment"], d["numerics"]
    expected = {f"mine.{k}": v for k, v in m.items() if k != "name"}
    expected.update({f"release.{c}": v for c, v in zip("xyz", r["position"])})
    expected.update({f"release.{c}": v for c, v in zip("uvw", r["velocity"])})
    expected.update({f"release.omega{i + 1}": v for i, v in enumerate(r["angular_velocity"])})
    expected.update({f"environment.{k}": v for k, v in e.items() if k != "current"})
    expected.update(
        {
            "current.kind": 2,
            "current.u": 0.6,
            "current.v": -0.2,
            "current.exponent": 0.2,
            "current.table_index": -1,
        }
    )
    expected.update(
        {f"sediment.{k}": v for k, v in sd.items() if k not in ("resistance", "rate_law", "pore_pressure")}
    )
    expected.update(
        {
            "sediment.profile_index": -1,
            "sediment.resistance": 1,
            "sediment.rate_law": 2,
            "sediment.pore_pressure": 1.0,
        }
    )
    expected.update(
        {
            f"numerics.{k}": v
            for k, v in nm.items()
            if k not in ("model", "integrator", "drag", "sediment_quadrature", "overburden_quadrature")
        }
    )
    expected.update(
        {
            # full() is an impact35 scenario: its model's tolerances
            "numerics.rtol": 1e-5,
            "numerics.atol": 1e-6,
            "numerics.slip_speed": 5e-3,
            "numerics.switch_speed": 5e-3,
            "numerics.sediment_quadrature": 0,
            "numerics.water_column": 0,  # default "munk_factor"
            "numerics.overburden_quadrature": 0,
        }
    )
    expected.update({"numerics.model": 1, "numerics.integrator": 0, "numerics.drag": 0.0})
    expected.update({"mine.shape": 0, "mine.top_ratio": 1.0})  # the default shape, the cylinder (issue 36)
    ref_q = Rotation.from_euler(
        "ZYX", [r["heading_deg"], r["pitch_deg"], r["roll_deg"]], degrees=True
    ).as_quat()
    ref_q = np.roll(ref_q, 1) * np.sign(ref_q[3])
    expected.update({f"release.q{i}": ref_q[i] for i in range(4)})
    assert set(expected) == set(layout.PARAM_NAMES)
    for name, value in expected.items():
        assert p[idx[name]] == pytest.approx(value, rel=1e-14, abs=1e-15), name
    # the module-level slot constants agree with the names
    assert p[layout.P_MASS] == 640.0 and p[layout.P_CHI] == -0.07
    assert p[layout.P_SED_NC] == 9.0 and p[layout.P_DEPTH] == 41.0


def test_to_params_tabulated_profiles_and_banks():
    d = base()
    d["environment"]["current"] = {
        "kind": "table",
        "depth": [0.0, 10.0, 30.0],
        "u": [0.5, 0.3, 0.0],
        "v": [0.0, 0.1, 0.0],
    }
    s = Scenario.from_dict(d)
    p, sed_bank, cur_bank = s.to_params()
    idx = layout.INDEX
    assert p[idx["sediment.profile_index"]] == 0 and sed_bank.shape == (1, 3, 2)
    np.testing.assert_array_equal(sed_bank[0], catalogue_profile("soft_clay").as_array())
    assert p[idx["current.kind"]] == 3 and p[idx["current.table_index"]] == 0
    np.testing.assert_array_equal(cur_bank[0], [[0, 10, 30], [0.5, 0.3, 0.0], [0, 0.1, 0]])
    # linear slots hold the seabed values and gradients of the class (for information)
    from mineburial.systems.mine.sediment_profiles import CATALOGUE

    c = CATALOGUE["soft_clay"]
    assert p[idx["sediment.strength"]] == c.strength
    assert p[idx["sediment.strength_gradient"]] == pytest.approx(c.strength_gradient, rel=1e-12)
    # a bank of several classes for an ensemble, NaN padded
    bank = pack_banks(
        [catalogue_profile("sand"), s.sediment.profile, config.load_example("exp2_barrel").sediment.profile]
    )
    assert bank.shape == (3, 3, 9) and np.isnan(bank[0, 0, 2])


def test_check_range_vectorised():
    v = np.array([-1.0, 0.0, 1e-9, 2.0, 50.0, 50.1, np.nan, np.inf])
    np.testing.assert_array_equal(
        check_range("mine.length", v), [False, False, True, True, True, False, False, False]
    )
    np.testing.assert_array_equal(check_range("release.pitch_deg", [-90, 90, 90.5]), [True, True, False])
    # aliases: file locations and environment.current.*
    assert check_range("release.position[2]", 5.0) and check_range("environment.current.u", 1.0)
    with pytest.raises(
        ScenarioError,
        match=r"unknown field 'mine.lenght': did you mean "
        r"'mine.length'",
    ):
        check_range("mine.lenght", 1.0)


def test_fields_table_is_consistent():
    for path, spec in FIELDS.items():
        assert spec.path == path and spec.low < spec.high and spec.units and spec.description
        if spec.default is not None:
            assert spec.contains(spec.default), path
    # every float slot of the layout that is a scenario value has a FieldSpec
    codes = {
        "current.kind",
        "current.table_index",
        "sediment.profile_index",
        "sediment.resistance",
        "sediment.rate_law",
        "sediment.pore_pressure",
        "numerics.model",
        "numerics.integrator",
        "numerics.drag",
        "numerics.sediment_quadrature",
        "numerics.water_column",
        "numerics.overburden_quadrature",
        "mine.shape",
    }
    assert set(layout.PARAM_NAMES) - codes <= set(FIELDS)
    # dataclass defaults agree with the table
    sed = Sediment(density=1500.0, strength=1000.0)
    for f in (
        "impact_factor",
        "rest_speed",
        "rate_coefficient",
        "reference_rate",
        "friction",
        "bearing_factor",
        "rupture_length",
        "permeability",
        "void_ratio",
    ):
        assert getattr(sed, f) == FIELDS[f"sediment.{f}"].default
    num = Numerics()
    for f in (
        "dt",
        "t_max",
        "t_max_fall",
        "rest_speed",
        "rest_spin",
        "rtol",
        "atol",
        "slip_speed",
        "switch_speed",
    ):
        assert getattr(num, f) == FIELDS[f"numerics.{f}"].default
    assert Current().exponent == FIELDS["current.exponent"].default


def test_docs_cover_every_field():
    text = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "scenario.md").read_text()
    for path in FIELDS:
        key = path.split(".")[-1]
        assert f"`{key}`" in text or f"`{path}`" in text, path
    for name in config.example_names():
        assert name in text


def test_check_params_cross_constraints():
    s = Scenario.from_dict(full())
    p, _, _ = s.to_params()
    P = np.tile(p, (8, 1))
    idx = layout.INDEX
    P[1, idx["mine.com_offset"]] = 1.2  # |chi| >= L/2
    P[2, idx["mine.inertia_axial"]] = 500.0  # J1 > 2 J2
    P[3, idx["release.z"]] = -41.0  # at the seabed
    P[4, idx["release.q0"]] *= 1.01  # not unit
    P[5, idx["numerics.model"]] = 2  # no such model
    P[6, idx["sediment.strength"]] = -1.0  # linear profile out of range
    P[7, idx["sediment.profile_index"]] = 3  # beyond the bank
    ok = check_params(P, n_sediment=1, n_current=0)
    np.testing.assert_array_equal(ok, [True] + [False] * 7)
    assert explain_params(P[0]) == []
    msgs = explain_params(P[1])
    assert len(msgs) == 1 and "mine.com_offset = 1.2" in msgs[0] and "mine.length = 2.1" in msgs[0]
    assert any("release.z > -environment.water_depth" in m for m in explain_params(P[3]))
    assert any("bank row < 1" in m for m in explain_params(P[7], n_sediment=1))
    # a tabulated profile makes the linear slots informational only
    P[6, idx["sediment.profile_index"]] = 0
    assert check_params(P[6], n_sediment=1)[0]


# ---------------------------------------------------------------------------
# distributions and samples against the field ranges (issue 12 items 5, 6)
# ---------------------------------------------------------------------------
ROOT = pathlib.Path(__file__).resolve().parents[1]


def _ensemble(**fields):
    """base() as an ensemble scenario with the dotted ``fields`` set."""
    d = base()
    for path, value in fields.items():
        section, key = path.split(".")
        d[section][key] = value
    return d


@pytest.mark.parametrize(
    "path",
    sorted(
        [
            *(p for p in (ROOT / "mineburial" / "data").rglob("*.toml") if p.parent.name != "calibration"),
            *(ROOT / "benchmarks" / "scenarios").glob("*.toml"),
        ]
    ),
    ids=lambda p: p.name,
)
def test_shipped_scenarios_pass_the_support_check(path):
    """The rule that refuses distributions reaching outside a range keeps every shipped
    example and benchmark scenario (normal masses, lognormal strengths) valid."""
    from mineburial.ensembles.engine import load_ensemble

    load_ensemble(path)


def test_pitch_uniform_on_full_circle_is_refused_at_load():
    """Regression: pitch_deg = uniform(-180, 180) ran drops at 155 deg."""
    from mineburial.ensembles.engine import load_ensemble

    d = _ensemble(**{"release.pitch_deg": {"distribution": "uniform", "low": -180.0, "high": 180.0}})
    with pytest.raises(
        ScenarioError,
        match=r"^release\.pitch_deg = \{distribution = \"uniform\", "
        r"low = -180, high = 180\} puts probability 0\.5 "
        r"outside the allowed range \[-90, 90\] deg",
    ):
        load_ensemble(d)


@pytest.mark.parametrize("mean,refused", [(300.0, False), (5.0, False), (4.0, True), (1.0, True)])
def test_normal_on_a_positive_field_is_refused_only_beyond_the_tolerance(mean, refused):
    """mass ~ normal(mean, 1) puts Phi(-mean) below 0 (scipy): 2.9e-7 at 5 sigma is within
    the 1e-6 tolerance, 3.2e-5 at 4 sigma is not, and the message gives that number."""
    from scipy.stats import norm

    table = {"distribution": "normal", "mean": mean, "std": 1.0}
    from mineburial.ensembles.distributions import from_dict

    d = from_dict(table, "mine.mass")
    outside = norm.cdf(-mean)
    assert (outside > config.SUPPORT_TOLERANCE) == refused
    if refused:
        with pytest.raises(
            ScenarioError,
            match=rf"^mine\.mass = .* puts probability "
            rf"{outside:.3g} outside the allowed range "
            r"\(0, 100000\] kg \(at most 1e-06",
        ):
            config.check_distribution("mine.mass", d)
    else:
        config.check_distribution("mine.mass", d)


def test_bounded_distributions_inside_the_range_are_accepted():
    from mineburial.ensembles.distributions import from_dict

    ok = [
        (
            "mine.mass",
            {"distribution": "truncated_normal", "mean": 1.0, "std": 5.0, "low": 0.5, "high": 20.0},
        ),  # the parent normal reaches below 0
        ("mine.mass", {"distribution": "uniform", "low": 0.0, "high": 10.0}),  # open end: P=0
        (
            "sediment.friction",
            {"distribution": "choice", "values": [0.3, 9.0], "weights": [1.0, 0.0]},
        ),  # a zero weight is never drawn
        ("release.position[2]", {"distribution": "uniform", "low": -5.0, "high": 5.0}),
        ("sediment.class", {"distribution": "choice", "values": ["sand", "mud"]}),  # labels
        ("not.a.field", {"distribution": "normal", "mean": 0.0, "std": 1.0}),
    ]
    for path, table in ok:
        config.check_distribution(path, from_dict(table, path))
    bad = from_dict(
        {"distribution": "choice", "values": [0.3, 9.0], "weights": [1.0, 1e-9]}, "sediment.friction"
    )
    with pytest.raises(
        ScenarioError,
        match=r"1 of its 2 values lie outside the allowed range "
        r"\[0, 5\] \(probability 1e-09\), e\.g\. 9",
    ):
        config.check_distribution("sediment.friction", bad)


def test_invalid_samples_are_counted_per_field():
    """Sampled values outside their ranges, counted by hand: mass (0, 1e5] kg has -2 and NaN
    out; pitch [-90, 90] has 95 and -91 (95 the farthest); a sediment-class index and an
    unknown name are not fields."""
    inputs = {
        "mine.mass": np.array([1.0, -2.0, 3.0, np.nan]),
        "release.pitch_deg": np.array([0.0, 95.0, -91.0, 10.0]),
        "release.velocity[0]": np.array([0.0, 1.0, 2.0, 3.0]),
        "sediment.class": np.array([0, 1, 5, 7]),
        "something": np.array([-1e9] * 4),
    }
    np.testing.assert_array_equal(config.check_samples(inputs), [True, False, False, False])
    found = config.invalid_samples(inputs)
    assert [(f.path, f.count, f.total) for f in found] == [("mine.mass", 2, 4), ("release.pitch_deg", 2, 4)]
    assert math.isnan(found[0].example) and found[1].example == 95.0
    assert str(found[1]) == (
        "release.pitch_deg: 2 of 4 sampled values are outside the allowed "
        "range [-90, 90] deg (e.g. 95); those drops are invalid_input"
    )
    assert config.check_samples({}, 3).tolist() == [True] * 3


def test_sampled_angle_outside_range_marks_the_drop_invalid(monkeypatch):
    """The packed rows hold the angles only as a quaternion, so check_params cannot see a
    sampled pitch of 120 deg: chunk_inputs must mark that drop invalid_input."""
    from mineburial.ensembles import engine
    from mineburial.ensembles.sampling import SampleTable
    from mineburial.systems.mine import ensemble as mine

    spec = engine.load_ensemble(
        _ensemble(**{"release.pitch_deg": {"distribution": "uniform", "low": 0.0, "high": 60.0}})
    )
    monkeypatch.setattr(
        mine,
        "sample_fields",
        lambda *a, **k: SampleTable({"release.pitch_deg": np.array([10.0, 120.0, -90.0])}),
    )
    _, valid, inputs = mine.chunk_inputs(spec, 0, 3)
    assert valid.tolist() == [True, False, True]
    assert inputs["release.pitch_deg"].tolist() == [10.0, 120.0, -90.0]


# ---------------------------------------------------------------------------
# a mine released partly inside the seabed (issue 12 item 12)
# ---------------------------------------------------------------------------
def test_release_partly_inside_the_seabed_is_refused():
    """Regression: such a release ran and reported a NaN impact speed. Geometry by hand:
    a horizontal cylinder of diameter 0.5 reaches 0.25 below its COM; nose down (pitch 90)
    with chi = 0.2 the nose is L/2 - chi = 0.8 below it."""

    def scenario(z, pitch, chi=0.0, embedded=False):
        d = base()
        d["mine"]["com_offset"] = chi
        d["release"] = {"position": [0.0, 0.0, z], "pitch_deg": pitch, "embedded": embedded}
        return Scenario.from_dict(d)

    scenario(-30.0 + 0.25, 0.0)  # touching
    with pytest.raises(
        ScenarioError,
        match=r"^release\.position\[2\] = -29\.8 m starts the mine "
        r"0\.05 m inside the seabed",
    ):
        scenario(-29.8, 0.0)
    scenario(-30.0 + 0.8, 90.0, chi=0.2)
    with pytest.raises(ScenarioError, match=r"0\.01 m inside the seabed.*release\.embedded = true"):
        scenario(-29.21, 90.0, chi=0.2)
    s = scenario(-29.8, 0.0, embedded=True)  # said on purpose
    assert s.release.embedded and Scenario.from_dict(s.to_dict()) == s
    with pytest.raises(ScenarioError, match=r"release\.embedded = 'yes' must be true or false"):
        scenario(-29.8, 0.0, embedded="yes")


def test_check_params_marks_partly_embedded_rows():
    p, _, _ = Scenario.from_dict(base()).to_params()
    P = np.tile(p, (3, 1))
    z = layout.INDEX["release.z"]
    P[:, z] = [
        -29.0,
        -30.0 + 0.25 * math.cos(math.radians(30.0)) + 1.0 * math.sin(math.radians(30.0)) + 1e-9,
        -29.5,
    ]  # above, touching, inside
    assert check_params(P, n_sediment=1, n_current=0).tolist() == [True, True, False]
    assert check_params(P, n_sediment=1, n_current=0, embedded=True).tolist() == [True] * 3
    assert any("entirely above the seabed" in m for m in explain_params(P[2], n_sediment=1))


# ---------------------------------------------------------------------------
# messages that named one of several problems, or the wrong one (issue 12 item 12)
# ---------------------------------------------------------------------------
def test_unknown_keys_are_all_named():
    d = base()
    d["release"]["positon"] = [0.0, 0.0, 1.0]
    d["release"]["pich_deg"] = 3.0
    with pytest.raises(
        ScenarioError,
        match=r"^\[release\]: unknown keys 'positon' \(did you mean "
        r"'position'\?\), 'pich_deg' \(did you mean "
        r"'pitch_deg'\?\): allowed: ",
    ):
        Scenario.from_dict(d)
    d = base()
    d["environment"]["current"] = {
        "kind": "uniform",
        "velocity": [0.1, 0.0],
        "exponent": 0.2,
        "surface_velocity": [0.0, 0.0],
    }
    with pytest.raises(
        ScenarioError,
        match=r"keys 'exponent', 'surface_velocity' are not used by "
        r"kind 'uniform'",
    ):
        Scenario.from_dict(d)


def test_an_ensemble_scenario_given_as_one_drop_says_so():
    d = base()
    d["mine"]["mass"] = {"distribution": "normal", "mean": 700.0, "std": 5.0}
    d["release"]["velocity"] = [0.0, 0.0, {"distribution": "uniform", "low": -2.0, "high": 0.0}]
    with pytest.raises(
        ScenarioError,
        match=r"^mine\.mass, release\.velocity\[2\] are distributions:"
        r" this is an ensemble scenario",
    ):
        Scenario.from_dict(d)
    d = base()
    d["ensemble"] = {"n": 10}
    with pytest.raises(ScenarioError, match=r"^the \[ensemble\] table belongs to an ensemble"):
        Scenario.from_dict(d)


def test_docs_name_only_examples_that_exist():
    """Regression: docs/maps.md told users to write `mineburial example default_ensemble`,
    which does not exist."""
    import re

    from mineburial.systems.mine.ensemble import DEFAULT_SCENARIO
    from mineburial.systems.restraint import ensemble as restraint_ensemble
    from mineburial.systems.restraint import model as restraint

    names = set(config.example_names()) | set(config.ensemble_example_names())
    names |= set(restraint.example_names()) | {restraint_ensemble.EXAMPLE_NAME}
    texts = [p.read_text() for p in [ROOT / "README.md", *(ROOT / "docs").glob("*.md")]]
    used = {m for t in texts for m in re.findall(r"mineburial example ([A-Za-z0-9_]+)", t)}
    assert used and used <= names, used - names
    assert config.example_path("default_soft_mud") == DEFAULT_SCENARIO
