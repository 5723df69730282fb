"""Sediment profiles: validation, interpolation, CSV/NetCDF cores, catalogue, banks."""

import math

import numpy as np
import pytest

from mineburial.errors import ScenarioError
from mineburial.systems.mine.sediment_profiles import (
    CATALOGUE,
    CATALOGUE_MAX_DEPTH,
    SedimentProfile,
    bearing_capacity_factors,
    catalogue_profile,
    class_names,
    drained_equivalent_strength,
    load_csv,
    load_file,
    load_netcdf,
    nc_clay_strength_gradient,
    pack_banks,
)

DEPTH = [0.0, 0.02, 0.06, 0.10, 0.30]
RHO = [1350.0, 1450.0, 1600.0, 1700.0, 1720.0]
S = [150.0, 400.0, 1300.0, 2000.0, 2400.0]


def test_evaluate_matches_numpy_interp_and_holds_constant_below():
    prof = SedimentProfile(DEPTH, RHO, S)
    z = np.linspace(-0.05, 0.6, 301)
    rho, s = prof.evaluate(z)
    np.testing.assert_array_equal(rho, np.interp(z, DEPTH, RHO))
    np.testing.assert_array_equal(s, np.interp(z, DEPTH, S))
    # hand values: midpoint of a segment is the mean of its ends (linear), exact to rounding
    r_mid, s_mid = prof.evaluate(0.04)
    assert r_mid == pytest.approx((1450.0 + 1600.0) / 2, rel=1e-14)
    assert s_mid == pytest.approx((400.0 + 1300.0) / 2, rel=1e-14)
    # constant below the last point, seabed value above the seabed
    assert prof.evaluate(5.0) == (1720.0, 2400.0)
    assert prof.evaluate(-1.0) == (1350.0, 150.0)


def test_single_point_profile_is_uniform():
    prof = SedimentProfile([0.0], [1500.0], [1000.0])
    rho, s = prof.evaluate([0.0, 0.5, 3.0])
    assert np.all(rho == 1500.0) and np.all(s == 1000.0)
    assert prof.surface_gradients() == (1500.0, 0.0, 1000.0, 0.0)


@pytest.mark.parametrize(
    "depth, rho, s, match",
    [
        ([0.01, 0.1], [1400, 1500], [100, 200], r"depth\[0\] = 0\.01 m: the first point must be"),
        (
            [0.0, 0.1, 0.1],
            [1400, 1500, 1500],
            [1, 2, 3],
            r"depth\[2\] = 0\.1 m: depths must be strictly increasing",
        ),
        ([0.0, 0.2, 0.1], [1400, 1500, 1500], [1, 2, 3], r"depth\[2\] = 0\.1 m"),
        (
            [0.0, 0.1],
            [900, 1500],
            [100, 200],
            r"density\[0\] = 900\.0 kg m-3 is outside the allowed range \[1000, 2700\] kg m-3",
        ),
        ([0.0, 0.1], [1400, 2800], [100, 200], r"density\[1\] = 2800\.0 kg m-3"),
        (
            [0.0, 0.1],
            [1400, 1500],
            [100, -1],
            r"strength\[1\] = -1\.0 Pa is outside the allowed range \[0, 1e\+06\] Pa",
        ),
        ([0.0, 0.1], [1400, 1500], [100], r"same length"),
        ([0.0, np.nan], [1400, 1500], [1, 2], r"non-finite"),
        ([], [], [], r"non-empty"),
    ],
)
def test_profile_validation_errors(depth, rho, s, match):
    with pytest.raises(ScenarioError, match=match):
        SedimentProfile(depth, rho, s, where="sediment.profile")


def test_profile_is_immutable_and_compares_by_value():
    a = SedimentProfile(DEPTH, RHO, S, name="core")
    b = SedimentProfile(list(DEPTH), list(RHO), list(S), name="core")
    assert a == b and hash(a) == hash(b)
    assert a != SedimentProfile(DEPTH, RHO, S, name="other")
    with pytest.raises(AttributeError):
        a.name = "x"
    with pytest.raises(ValueError):
        a.depth[0] = 1.0
    assert SedimentProfile.from_dict(a.to_dict()) == a


def test_csv_core(tmp_path):
    path = tmp_path / "core.csv"
    # columns in another order, an extra column, comments and blank lines
    lines = ["# gravity core 7, Monterey Bay", "strength_pa,depth_m,note,density_kg_m3"]
    lines += [f"{s},{d},slice{i},{r}" for i, (d, r, s) in enumerate(zip(DEPTH, RHO, S))]
    path.write_text("\n".join(lines[:3]) + "\n\n" + "\n".join(lines[3:]) + "\n")
    prof = load_csv(path)
    np.testing.assert_array_equal(prof.depth, DEPTH)
    np.testing.assert_array_equal(prof.density, RHO)
    np.testing.assert_array_equal(prof.strength, S)
    assert prof.name == "core" and str(path.resolve()) in prof.source
    assert load_file("core.csv", base_dir=tmp_path) == prof


def test_csv_core_errors(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("depth_m,density_kg_m3,strength_kpa\n0,1400,1\n")
    with pytest.raises(ScenarioError, match=r"missing column 'strength_pa' \(found 'strength_kpa'\)"):
        load_csv(bad)
    bad.write_text("depth_m,density_kg_m3,strength_pa\n0,1400,abc\n")
    with pytest.raises(ScenarioError, match=r"line 2, column 3 \('strength_pa'\): not a number$"):
        load_csv(bad)
    with pytest.raises(ScenarioError, match="cannot read"):
        load_csv(tmp_path / "missing.csv")
    with pytest.raises(ScenarioError, match=r"unknown file type '\.txt'"):
        load_file(tmp_path / "core.txt")


def _write_nc(path, units=("cm", "g cm-3", "kPa"), positive="down", drop=None, scales=(100.0, 1e-3, 1e-3)):
    import netCDF4

    with netCDF4.Dataset(str(path), "w") as ds:
        ds.createDimension("z", len(DEPTH))
        for name, values, unit, scale in zip(
            ("depth", "density", "strength"), (DEPTH, RHO, S), units, scales
        ):
            if name == drop:
                continue
            v = ds.createVariable(name, "f8", ("z",))
            v[:] = np.array(values) * scale
            if unit is not None:
                v.units = unit
            if name == "depth":
                v.positive = positive


def test_netcdf_core_converts_units_to_si(tmp_path):
    path = tmp_path / "core.nc"
    _write_nc(path)  # depth in cm, density in g cm-3, strength in kPa
    prof = load_netcdf(path)
    np.testing.assert_allclose(prof.depth, DEPTH, rtol=0, atol=1e-15)
    np.testing.assert_allclose(prof.density, RHO, rtol=1e-15)
    np.testing.assert_allclose(prof.strength, S, rtol=1e-15)
    assert load_file("core.nc", base_dir=tmp_path) == prof
    _write_nc(tmp_path / "si.nc", units=("m", "kg m-3", "Pa"), scales=(1.0, 1.0, 1.0))
    si = load_netcdf(tmp_path / "si.nc")
    np.testing.assert_array_equal(si.as_array(), np.array([DEPTH, RHO, S]))
    # a file in g cm-3 labelled kg m-3 is caught by the density range
    _write_nc(tmp_path / "mislabelled.nc", units=("cm", "kg m-3", "kPa"))
    with pytest.raises(ScenarioError, match=r"density\[0\] = 1\.35 kg m-3 is outside"):
        load_netcdf(tmp_path / "mislabelled.nc")


def test_netcdf_core_errors(tmp_path):
    _write_nc(tmp_path / "a.nc", units=("m", None, "Pa"))
    with pytest.raises(ScenarioError, match="variable 'density' has no units"):
        load_netcdf(tmp_path / "a.nc")
    _write_nc(tmp_path / "b.nc", units=("m", "kg m-3", "psi"))
    with pytest.raises(ScenarioError, match="variable 'strength' has units 'psi'"):
        load_netcdf(tmp_path / "b.nc")
    _write_nc(tmp_path / "c.nc", drop="strength")
    with pytest.raises(ScenarioError, match="missing variable 'strength'"):
        load_netcdf(tmp_path / "c.nc")
    _write_nc(tmp_path / "d.nc", positive="up")
    with pytest.raises(ScenarioError, match="positive down"):
        load_netcdf(tmp_path / "d.nc")


def test_vesic_bearing_factors_match_published_table():
    # Vesic (1973/1975) table at phi = 30 deg: N_c = 30.14, N_q = 18.40, N_gamma = 22.40
    nc, nq, ng = bearing_capacity_factors(30.0)
    assert (nc, nq, ng) == pytest.approx((30.14, 18.40, 22.40), abs=0.006)
    # phi -> 0: N_c -> pi + 2 (Prandtl), N_q -> 1
    nc0, nq0, _ = bearing_capacity_factors(1e-6)
    assert nc0 == pytest.approx(math.pi + 2, rel=1e-6) and nq0 == pytest.approx(1.0, rel=1e-6)


def test_equivalent_strength_and_nc_gradient_closed_forms():
    # NC clay: 0.22 * (1500 - 1025) * 9.81 Pa/m = 1025.1 Pa/m (Mesri 1975 ratio)
    assert nc_clay_strength_gradient(1500.0) == pytest.approx(0.22 * 475 * 9.81, rel=1e-15)
    # sand proxy: q = 0.5 gamma' B N_gamma + gamma' z N_q divided by pi + 2
    s0, k = drained_equivalent_strength(30.0, 1925.0, width=0.5)
    gamma = 900.0 * 9.81
    assert s0 == pytest.approx(0.5 * gamma * 0.5 * 22.40 / 5.1416, rel=2e-4)
    assert k == pytest.approx(gamma * 18.40 / 5.1416, rel=2e-4)


def test_catalogue_classes():
    names = class_names()
    for required in ("very_soft_clay", "soft_clay", "firm_clay", "silty_mud", "sandy_silt", "sand"):
        assert required in names
    for name in names:
        c = CATALOGUE[name]
        assert c.description and c.source
        prof = catalogue_profile(name)
        assert prof.name == name and name in prof.source
        # two-point table reproduces the linear class exactly on [0, max depth]
        z = np.array([0.0, 0.37, 2.0, CATALOGUE_MAX_DEPTH])
        rho, s = prof.evaluate(z)
        np.testing.assert_allclose(rho, c.density + c.density_gradient * z, rtol=1e-14)
        np.testing.assert_allclose(s, c.strength + c.strength_gradient * z, rtol=1e-14)
        assert 1000.0 <= c.density <= 2700.0 and c.strength >= 0 and c.strength_gradient >= 0
    # clays: mudline strengths in the Terzaghi & Peck (1967) consistency classes
    assert CATALOGUE["very_soft_clay"].strength < 12.5e3
    assert CATALOGUE["soft_clay"].strength < 25e3
    assert 25e3 <= CATALOGUE["firm_clay"].strength <= 50e3
    assert 50e3 <= CATALOGUE["stiff_clay"].strength <= 100e3
    # soft marine clay gradient in the typical 1-2 kPa/m range (normally consolidated)
    assert 1e3 <= CATALOGUE["soft_clay"].strength_gradient <= 2e3
    # the soft classes' mudline strengths lie in the fall-cone range of seed 000 Table 4
    for name in ("very_soft_clay", "soft_clay", "silty_mud"):
        assert 6.3 <= CATALOGUE[name].strength <= 25e3


def test_unknown_class_suggests_nearest():
    with pytest.raises(
        ScenarioError,
        match=r"unknown sediment class 'sof_clay': did you mean "
        r"'soft_clay'\? allowed: .*very_soft_clay",
    ):
        catalogue_profile("sof_clay")


def test_pack_banks_pads_with_nan():
    a = SedimentProfile(DEPTH, RHO, S)
    b = catalogue_profile("sand")
    bank = pack_banks([b, a])
    assert bank.shape == (2, 3, 5) and bank.dtype == np.float64
    np.testing.assert_array_equal(bank[1], np.array([DEPTH, RHO, S]))
    np.testing.assert_array_equal(bank[0, :, :2], b.as_array())
    assert np.all(np.isnan(bank[0, :, 2:]))
    assert pack_banks([]).shape == (0, 3, 1)
    np.testing.assert_array_equal(pack_banks([np.ones((3, 2))])[0], np.ones((3, 2)))
    with pytest.raises(ScenarioError, match="shape"):
        pack_banks([np.ones((2, 2))])
