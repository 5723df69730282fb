"""Tests of the fast rule's sliver panels (issue 34 item 4; mineburial/kernels/mine/sediment/fast.py,
``PANEL_SKIP``): a lateral panel narrower than ``PANEL_SKIP`` of the embedded half-arc carries no
nodes, one twice as wide full weight, linear in between.

* against scipy's adaptive quadrature of the same traction integrand (``quad_force_torque`` of
  tests/test_sediment_fast.py) at poses of a drop in one vertical plane, where the slivers are
  (the breakpoints of the two body ends coincide to rounding): the rule with the skip is as
  accurate as the rule with every panel;
* continuity: along a path that opens a sliver through the ramp (the out-of-plane velocity from 0),
  sampling 10 times more finely divides the largest step by about 10 (a skip without the ramp would
  leave a jump of the sliver's share);
* the bound of ``PANEL_SKIP``: what the skip changes is at most a few ``PANEL_SKIP`` of the force
  scale (int |t| dA from scipy).
"""

import math

import numpy as np
import pytest
from test_sediment_fast import (
    SLAP_MINE,
    SLAP_POSES,
    _largest_step,
    law_of,
    quad_force_torque,
    slap_params,
)

from mineburial.kernels.mine.sediment.fast import (
    PANEL_SKIP,
    _cap,
    fast_tractions,
    fast_tractions_every_panel,
)

EMPTY_BANK = np.full((1, 3, 2), np.nan)


def _args(L, R, chi, c2, d0, vb):
    return (
        float(L),
        float(R),
        float(chi),
        float(c2[0]),
        float(c2[1]),
        float(c2[2]),
        float(d0),
        tuple(float(v) for v in vb),
    )


def _rules(L, R, chi, c2, d0, vb, p):
    """(with the skip, every panel) body-frame (f1, f2, f3, m1, m2, m3)."""
    a = _args(L, R, chi, c2, d0, vb)
    law = law_of(p, R)
    return np.array(fast_tractions(*a, law, EMPTY_BANK)), np.array(
        fast_tractions_every_panel(*a, law, EMPTY_BANK)
    )


def _planar(k, v2=0.0):
    """Slap pose k (a drop in the body's x-z plane: no roll, pitch rate only), with the out-of-plane
    velocity v2 (body frame)."""
    c2, d0, vb = SLAP_POSES[k]
    c2 = np.asarray(c2, float) / np.linalg.norm(c2)
    vb = np.array(vb, float)
    vb[1] = v2
    return c2, d0, vb


@pytest.mark.parametrize("k, v2", [(0, 0.0), (2, 0.0), (2, 3e-7)])
def test_skip_keeps_the_accuracy_against_scipy(k, v2):
    """At a planar pose (and one with a tiny out-of-plane velocity, slivers of ~1e-7 rad) the rule
    with the skip is within 2.5 % of scipy's quadrature (as the rule is required to be there) and
    not farther from it than the rule with every panel by more than 1e-5 of the force (torque)
    scale; the two differ by at most 4 PANEL_SKIP of the scale."""
    c2, d0, vb = _planar(k, v2)
    p = slap_params()
    F, M, sf, sm = quad_force_torque(*SLAP_MINE, c2, d0, vb, p)
    assert sf > 0.0 and sm > 0.0
    new, every = _rules(*SLAP_MINE, c2, d0, vb, p)
    ef_new = np.linalg.norm(new[:3] - F) / sf
    em_new = np.linalg.norm(new[3:] - M) / sm
    ef_all = np.linalg.norm(every[:3] - F) / sf
    em_all = np.linalg.norm(every[3:] - M) / sm
    assert ef_new < 0.025 and em_new < 0.025, (ef_new, em_new)
    assert ef_new <= ef_all + 1e-5 and em_new <= em_all + 1e-5, (ef_new, ef_all, em_new, em_all)
    assert np.linalg.norm(new[:3] - every[:3]) <= 4 * PANEL_SKIP * sf
    assert np.linalg.norm(new[3:] - every[3:]) <= 4 * PANEL_SKIP * sm


def test_force_is_continuous_as_a_sliver_opens():
    """The out-of-plane velocity v2 from 0 to 4e-6 m/s opens slivers between the breakpoints of the
    two body ends (width ~ v2 / |v.n| ~ 1e-6 rad) through the ramp: sampling 10 times more finely
    divides the largest change between neighbours by 4 at least (continuous; a jump would keep it),
    on the force and on the torque."""
    p = slap_params()

    def fun(s):
        c2, d0, vb = _planar(2, s)
        return _rules(*SLAP_MINE, c2, d0, vb, p)[0]

    # what the slivers carry on this path: the difference to every panel, at its largest
    every = np.array([_rules(*SLAP_MINE, *_planar(2, s), p)[1] for s in np.linspace(0.0, 4e-6, 41)])
    new = np.array([fun(s) for s in np.linspace(0.0, 4e-6, 41)])
    share = np.max(np.abs(new - every)) / np.max(np.abs(every))
    assert share > 1e-12  # the path does cross slivers (else the test would test nothing)
    coarse = _largest_step(fun, 0.0, 4e-6, 200)
    fine = _largest_step(fun, 0.0, 4e-6, 2000)
    assert fine < 0.25 * coarse, (coarse, fine, share)


def test_no_skip_without_slivers():
    """A general pose (roll, yaw and pitch rates, out-of-plane velocity of the order of the others):
    no panel is a sliver, and the rule is the rule with every panel to the bit."""
    c2 = np.array([0.298, 0.12, 0.947])
    c2 /= np.linalg.norm(c2)
    vb = (0.634, 0.3, -1.129, 0.15, 1.922, 0.25)
    new, every = _rules(*SLAP_MINE, c2, -0.4176, vb, slap_params())
    assert np.array_equal(new, every)
    assert math.isfinite(new[0])


def _nose_cap(w3, skip):
    """The embedded end cap (x = xa) of slap pose 2 with a slower axial speed, so that the delta chord
    crosses the rim: with no yaw rate the chord is parallel to the seabed chord and its two rim points
    are at one u; a yaw rate w3 splits them by ~w3 (a sliver u-panel)."""
    L, R, chi = SLAP_MINE
    c2, d0, _ = _planar(2)
    vb = (0.3, 0.0, -1.129, 0.0, 1.922, float(w3))
    law = law_of(slap_params(), R)
    xa = -0.5 * L - chi
    return np.array(_cap(xa, -1.0, R, float(d0), *map(float, c2), vb, law, EMPTY_BANK, skip))


def test_cap_is_continuous_as_a_sliver_opens():
    """The cap's u-panels: the yaw rate w3 from 0 to 4e-6 rad/s opens a sliver u-panel through the ramp.
    The cap with the skip differs from the cap with every panel on the path (the sliver is there) by at
    most 4 PANEL_SKIP of its largest force, and sampling 10 times more finely divides its largest step
    by 4 at least."""
    s = np.linspace(0.0, 4e-6, 41)
    new = np.array([_nose_cap(w, PANEL_SKIP) for w in s])
    every = np.array([_nose_cap(w, 0.0) for w in s])
    scale = np.max(np.linalg.norm(every[:, :3], axis=1))
    assert scale > 0.0
    share = np.max(np.abs(new - every)[:, :3]) / scale
    assert 1e-12 < share <= 4 * PANEL_SKIP, share
    coarse = _largest_step(lambda w: _nose_cap(w, PANEL_SKIP), 0.0, 4e-6, 200)
    fine = _largest_step(lambda w: _nose_cap(w, PANEL_SKIP), 0.0, 4e-6, 2000)
    assert fine < 0.25 * coarse, (coarse, fine, share)
