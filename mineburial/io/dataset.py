"""The one CF dataset builder of every file mineburial writes.

:func:`build` turns arrays into an :class:`xarray.Dataset` whose every variable takes its
metadata (dims, dtype, units, ``long_name``, ``comment``, flags, netCDF ``_FillValue``)
from the one variable registry :mod:`mineburial.io.variables`, in the family of the file's
``kind`` (:data:`mineburial.io.variables.FAMILIES`), and whose global attributes carry
what every mineburial file must (:func:`standard_attrs`): ``Conventions``,
``mineburial_version``, ``source``, ``date_created`` and ``history``. The layers that
compute a file's contents (ensembles, the single drop, the restraining system, the
sensitivity analysis, the maps, the comparisons) hand their arrays and their own global
attributes to it; none of them writes ``Conventions`` or the version itself. docs/notes/output.md lists the
families and the attributes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial._version import __version__
from mineburial.io import netcdf as ncio
from mineburial.io import variables as V

__all__ = ["build", "standard_attrs", "registry_mismatches"]


def standard_attrs(kind: str, attrs: Mapping[str, Any] | None = None, *, version=None) -> dict[str, Any]:
    """The global attributes of a file of ``kind``: ``attrs`` with the ones every mineburial
    file carries filled in where ``attrs`` does not give them: ``Conventions``
    (:data:`mineburial.io.netcdf.CONVENTIONS`, always), ``mineburial_version`` (``version``,
    default this package's), ``source`` (``"mineburial <version>"``), ``date_created`` (now,
    UTC) and ``history`` (one line: date, version and what the file is,
    :data:`mineburial.io.variables.FAMILY_TITLES`). ``None`` values are dropped and bools
    stored as int8 (:func:`mineburial.io.netcdf.clean_attrs`)."""
    if kind not in V.FAMILY_TITLES:
        raise KeyError(V._unknown("dataset kind", kind, V.FAMILY_TITLES))
    version_s = str(version) if version is not None else __version__
    given = dict(attrs or {})
    created = given.get("date_created") or ncio.utc_now()
    out = {"Conventions": ncio.CONVENTIONS, **{k: v for k, v in given.items() if k != "Conventions"}}
    out.setdefault("mineburial_version", version_s)
    out.setdefault("source", f"mineburial {version_s}")
    out["date_created"] = created
    out.setdefault("history", f"{created} mineburial {version_s}: {V.FAMILY_TITLES[kind]}")
    return ncio.clean_attrs(out)


def _data_array(family: Mapping[str, V.Variable], name: str, value, names: Mapping[str, str]) -> xr.DataArray:
    """``value`` as the declared variable ``name``: an array, ``(array, extra_attrs)`` (run-time
    attributes such as flags a kernel module owns), or a DataArray already made from a
    declaration (a sampled input ``input_*``, a statistics Dataset's variable) or copied from an
    input (its dims are then the file's). ``names`` renames declared names and dims."""
    out_name = names.get(name, name)
    if isinstance(value, xr.DataArray):
        if name not in family and not name.startswith("input_"):
            raise KeyError(V._unknown("output variable", name, family))
        return value.rename(out_name) if value.name != out_name else value
    if name not in family:
        raise KeyError(V._unknown("output variable", name, family))
    decl = family[name]
    if names:
        decl = dataclasses.replace(decl, name=out_name, dims=tuple(names.get(d, d) for d in decl.dims))
    if isinstance(value, tuple) and len(value) == 2 and isinstance(value[1], Mapping):
        array, extra = value
        return decl.data_array(array, **extra)
    return decl.data_array(value)


def build(
    variables: Mapping[str, Any],
    coords: Mapping[str, Any] | None = None,
    attrs: Mapping[str, Any] | None = None,
    *,
    kind: str,
    version=None,
    names: Mapping[str, str] | None = None,
) -> xr.Dataset:
    """The Dataset of a file of ``kind`` (a key of :data:`mineburial.io.variables.FAMILIES`).

    ``variables`` and ``coords`` map registry names of that family to their values
    (:func:`_data_array`: arrays, ``(array, extra_attrs)`` or DataArrays made from a
    declaration); ``attrs`` are the file's own global attributes, completed by
    :func:`standard_attrs`. A name the family does not declare raises ``KeyError``
    naming the closest declared ones. The netCDF encodings (fill values) of the
    declarations are kept on the Dataset's variables for
    :func:`mineburial.io.netcdf.write_netcdf`. ``names`` maps declared names of dims and
    variables to this file's (a map's horizontal axes and grid mapping are its grid's)."""
    family, names = V.family(kind), dict(names or {})
    data = {names.get(n, n): _data_array(family, n, value, names) for n, value in variables.items()}
    cs = {names.get(n, n): _data_array(family, n, value, names) for n, value in (coords or {}).items()}
    # the Dataset is made from plain Variables, the coordinates the DataArrays carry collected
    # once: from DataArrays xarray aligns every variable against every coordinate (measured
    # 0.25 s of a 1,000-drop run's 6.4 s, against 0.01 s so)
    coord_vars = {name: da.variable for name, da in cs.items()}
    for da in data.values():
        for cname, c in da.coords.items():
            coord_vars.setdefault(cname, c.variable)
    ds = xr.Dataset({name: da.variable for name, da in data.items()}, coords=coord_vars)
    for name, da in {**data, **cs}.items():  # construction may drop encodings: restore them
        ds.variables[name].encoding.update(da.encoding)  # the Variable: no DataArray built
    ds.attrs = standard_attrs(kind, attrs, version=version)
    return ds


def registry_mismatches(ds: xr.Dataset, kind: str, names: Mapping[str, str] | None = None) -> list[str]:
    """What in ``ds`` does not come from the registry's ``kind`` family: a variable the family
    does not declare (sampled inputs ``input_*`` aside), a declared attribute missing or with
    another value (run-time attributes only present), another dtype or dims (of a variable
    copied from an input: dims only); and a missing ``Conventions`` or ``mineburial_version``.
    ``names``: as given to :func:`build`. Empty for a file made by :func:`build`; the tests'
    check that every writer goes through it."""
    family, names = V.family(kind), dict(names or {})
    declared_as = {n: n for n in family} | {names[n]: n for n in family if n in names}
    required = ("Conventions", "mineburial_version")
    out = [f"global attribute {k} missing" for k in required if k not in ds.attrs]
    for name, var in ds.variables.items():
        name = str(name)
        if name.startswith("input_") and "scenario_path" in var.attrs:
            continue
        decl = family.get(declared_as.get(name, ""))
        if decl is None:
            out.append(f"{name}: not declared in the {kind} family")
            continue
        dims = tuple(names.get(d, d) for d in decl.dims)
        if var.dims != dims or (not decl.from_input and var.dtype != np.dtype(decl.dtype)):
            out.append(f"{name}: {var.dims} {var.dtype}, declared {dims} {decl.dtype}")
        for key, value in ({} if decl.from_input else decl.cf_attrs()).items():
            if key in decl.runtime_attrs and key in var.attrs:
                continue
            if key not in var.attrs or not np.array_equal(np.asarray(var.attrs[key]), np.asarray(value)):
                out.append(f"{name}: attribute {key} = {var.attrs.get(key)!r}, declared {value!r}")
        if decl.runtime_flags and "flag_values" not in var.attrs:
            out.append(f"{name}: the flags of {decl.runtime_flags} missing")
    return out
