"""A sweep of many points one way and 1 or 2 the other: held-out scoring never leaves out a
direction's end points, so the short direction's points judge one curve for both directions by
their chi-square in the long direction's noise (``fit.textbook_laws.symmetry_rejected``)."""
import numpy as np
import pytest

import fricgen


def stribeck(speed):
    return 0.5 + 0.4 / (1 + (speed / 0.01) ** 2) + 0.6 * speed


def unbalanced(seed, backward, flat=True, noise=0.01):
    """15 log-spaced Stribeck points forward; ``backward`` points at 0.05-0.2 backward, of a flat
    friction 1 + 0.6 |v| (``flat``) or of the forward curve."""
    rng = np.random.default_rng(seed)
    forward, back = np.geomspace(1e-3, 0.3, 15), np.geomspace(0.05, 0.2, backward)
    f_back = 1.0 + 0.6 * back if flat else stribeck(back)
    v = np.concatenate([forward, -back])
    return v, np.concatenate([stribeck(forward), -f_back]) + noise * rng.standard_normal(v.size)


@pytest.mark.parametrize("seed, backward", [(1000, 2), (1001, 2), (1002, 1)])
def test_the_short_directions_points_reject_one_curve_for_both(seed, backward):
    """One curve for both had been kept 0.38 N (38 noise levels) off the 2 backward points."""
    v, f = unbalanced(seed, backward)
    report = fricgen.train({"v": v, "f": f}, warn=lambda line: None)
    assert "symmetric" not in report.law.name
    assert any("reject one curve for both" in line for line in report.law.left_out)
    assert np.max(np.abs(report.model.force(v[v < 0]) - f[v < 0])) < 0.05


@pytest.mark.parametrize("seed", [1003, 1004, 1005])
def test_points_on_the_long_directions_curve_keep_it_for_both(seed):
    v, f = unbalanced(seed, 2, flat=False)
    report = fricgen.train({"v": v, "f": f}, warn=lambda line: None)
    assert not any("reject one curve for both" in line for line in report.law.left_out)
