import json

import numpy as np
import pytest

from fricgen.data import (DataError, Sweep, choose_vs_max, identify_viscous, prepare,
                          read_sweep_csv, sweep_csv_text, synthesize_benchmark)
from fricgen.friction import preset


def test_benchmark_follows_section_2(bench, paper_friction):
    v_sat = 0.06
    train_low = bench.train.v[bench.train.v <= v_sat]
    assert train_low.size == 200 and train_low.min() >= 0
    assert np.all(np.abs(bench.train.f - paper_friction(bench.train.v)) <= 0.5)
    assert bench.test.v.size == 200 and bench.test.v.max() <= v_sat
    assert np.all(np.abs(bench.test.f - paper_friction(bench.test.v)) <= 0.5)
    assert np.allclose(bench.theory.v, np.linspace(0, v_sat, 500))
    # theory is noise free, with the right-hand limit at v = 0
    assert bench.theory.f[0] == pytest.approx(44.0)
    assert np.allclose(bench.theory.f[1:], paper_friction(bench.theory.v[1:]))


def test_training_set_has_the_two_added_points(bench, paper_friction):
    d = bench.dataset
    assert d.x.size == 202
    slowest = np.sort(bench.train.v)[:4]
    f_slowest = bench.train.f[np.argsort(bench.train.v)[:4]]
    assert d.x[0] == 0.0
    assert d.t[0] == pytest.approx(d.scaling.k_out * (f_slowest - d.viscous * slowest).mean())
    assert slowest.max() < 0.06
    assert d.x[-1] == pytest.approx(1.0)
    f_sat = float(paper_friction(0.06))
    assert d.t[-1] == pytest.approx(d.scaling.k_out * (f_sat - d.viscous * 0.06))


def test_the_point_at_rest_carries_no_viscous_force_of_the_slowest_speed():
    """A log whose slowest steady speed is far from rest (a 67 Hz log's reversals leave out
    everything below 1.8 rad/s): the point added at v = 0 holds the curve less its viscous line
    at the slowest rows, so that the model does not add B v_min there a second time (a hump
    of B v_min below the data: 2.8 Nm where the truth was 1.4)."""
    v = np.linspace(1.8, 7.0, 200)
    f = 0.4 + 1.3 * v                               # Coulomb + viscous, no Stribeck drop
    d = prepare(Sweep(v, f), vs_max=1.5)            # B from the rows beyond 4.5 rad/s
    assert d.t[0] / d.scaling.k_out == pytest.approx(0.4, abs=0.02)


def test_normalization_defaults(bench):
    d = bench.dataset
    assert d.scaling.k_in == pytest.approx(1 / 0.06)
    assert d.t.max() == pytest.approx(1.0)
    assert 0 <= d.x.min() and d.x.max() == pytest.approx(1.0)


def test_viscous_identification_recovers_B(bench):
    # 100 high-speed points with +-0.5 N noise: the slope is known to about 0.5 N s/m
    assert bench.dataset.viscous == pytest.approx(57.5, abs=1.0)
    v = np.linspace(1, 2, 50)
    B, f0, rejected = identify_viscous(Sweep(v, 3.0 + 7.0 * v))
    assert (B, f0) == pytest.approx((7.0, 3.0))


def test_negative_velocities_fold_onto_the_same_model(bench):
    flip = np.arange(len(bench.train)) % 2 == 0
    mirrored = Sweep(np.where(flip, -bench.train.v, bench.train.v),
                     np.where(flip, -bench.train.f, bench.train.f))
    a = prepare(bench.train, vs_max=0.02)
    b = prepare(mirrored, vs_max=0.02)
    assert np.allclose(np.sort(a.x), np.sort(b.x)) and np.allclose(np.sort(a.t), np.sort(b.t))
    assert a.viscous == pytest.approx(b.viscous)


def test_vs_max_choice_is_near_the_truth(paper_friction):
    """Table 1's largest Stribeck velocity is 0.02 m/s: the cross-validated choice lands near it
    (or says the data have no linear region), and prepare records the choice."""
    for seed in range(3):
        b = synthesize_benchmark(paper_friction, seed=seed)
        chosen = choose_vs_max(b.train.folded())
        assert 0.01 <= chosen.vs_max <= 0.07
        assert len(chosen.curve) >= 5 and all(e > 0 for _, e in chosen.curve)
        dataset = prepare(b.train)
        assert dataset.vs_max_estimated and dataset.stribeck_range == chosen


def test_one_direction_sweeps_to_ten_vs_max_are_never_refused():
    """Eight noise draws of one law, one direction, speeds up to 10 vs_max: every one gives a
    training set (an estimate once refused 2 of 8 as 'no high-speed data for B')."""
    law = preset("paper3")
    for seed in range(8):
        rng = np.random.default_rng(seed)
        v = np.concatenate([rng.uniform(0, 0.06, 200), rng.uniform(0.06, 0.2, 100)])
        dataset = prepare(Sweep(v, law(v) + rng.uniform(-0.5, 0.5, v.size)))
        assert 0.01 <= dataset.v_sat / 3 <= 0.07


def test_a_sweep_without_linear_region_fits_B_with_the_rest():
    """Speeds only up to 2.5 vs_max of a rational law: no straight high-speed part. The choice
    says so, v_sat is the fastest speed, and B comes from the joint fit (not refused)."""
    rng = np.random.default_rng(0)
    v = rng.uniform(0.0, 0.05, 300)
    f = 10.0 + 20.0 / (1.0 + v / 0.02) + 30.0 * v + rng.normal(0.0, 0.05, v.size)
    chosen = choose_vs_max(Sweep(v, f))
    assert not chosen.linear_region and "no linear" in chosen.describe()
    dataset = prepare(Sweep(v, f))
    assert dataset.v_sat == pytest.approx(v.max())
    assert dataset.viscous == pytest.approx(chosen.viscous) and dataset.viscous >= 0


def test_a_sweep_that_ends_within_the_stribeck_drop_gets_no_falling_line():
    """Speeds up to 0.6 of a Gaussian Stribeck velocity: beyond every candidate v_sat the force
    still falls. No candidate's falling line (B < 0) is taken for a linear region, B >= 0 comes
    from the joint fit, and the friction never reverses beyond the data."""
    rng = np.random.default_rng(3)
    v = rng.uniform(0.0015, 0.006, 400)
    f = 8.0 + 6.0 * np.exp(-(v / 0.01) ** 2) + 40.0 * v + rng.normal(0.0, 0.05, v.size)
    chosen = choose_vs_max(Sweep(v, f))
    assert chosen.falling and not chosen.linear_region and chosen.viscous >= 0
    assert "still falls at the fastest speeds" in chosen.describe()
    dataset = prepare(Sweep(v, f))
    assert dataset.viscous >= 0 and dataset.v_sat == pytest.approx(v.max())


def test_csv_round_trip(tmp_path, bench):
    path = tmp_path / "sweep.csv"
    path.write_text(sweep_csv_text(bench.train))
    back = read_sweep_csv(path)
    assert np.array_equal(back.v, bench.train.v) and np.array_equal(back.f, bench.train.f)


def _csv(tmp_path, text):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    return p


@pytest.mark.parametrize("body, message", [
    ("v,f\n" + "0.1,nan\n" * 30, "NaN or infinite"),
    ("v,f\n" + "0.1,inf\n" * 30, "NaN or infinite"),
    ("v,f\n" + "0.1,abc\n" * 30, "non-numeric"),
    ("v,g\n" + "0.1,1\n" * 30, "missing column 'f'"),
    ("v,f\n" + "0.1,1\n" * 2, "need at least 3"),
    ("", "empty file"),
])
def test_bad_sweep_csv_is_named(tmp_path, body, message):
    with pytest.raises(DataError, match=message):
        read_sweep_csv(_csv(tmp_path, body))


def test_no_high_speed_data_is_refused(bench):
    low = Sweep(bench.train.v[bench.train.v <= 0.06], bench.train.f[bench.train.v <= 0.06])
    with pytest.raises(DataError, match="no high-speed data for B"):
        prepare(low, vs_max=0.02)


@pytest.mark.parametrize("vs_max", [0.0, -0.02, float("nan")])
def test_non_positive_vs_max_is_refused(bench, vs_max):
    with pytest.raises(DataError, match="vs_max must be > 0"):
        prepare(bench.train, vs_max=vs_max)


def test_force_against_the_sign_of_v_is_refused(bench):
    """Friction acts with the sign of v in [F1]; a flipped v, force or current is named."""
    flipped = Sweep(bench.train.v, -bench.train.f)
    with pytest.raises(DataError, match="opposite sign of v"):
        prepare(flipped, vs_max=0.02)
    prepare(bench.train, vs_max=0.02)          # the same rows with the right sign are fine


@pytest.mark.parametrize("note", ["", "\tnote"], ids=["numbers only", "with a text column"])
def test_tab_separated_csv_reads_as_the_comma_separated_one(tmp_path, bench, note):
    """The delimiter is read off the header: a tab-separated export needs no conversion (the
    text column takes the careful reader, the numbers alone numpy's)."""
    text = sweep_csv_text(bench.train).replace(",", "\t").splitlines()
    rows = [text[0] + note] + [r + ("\tok" if note else "") for r in text[1:]]
    back = read_sweep_csv(_csv(tmp_path, "\n".join(rows) + "\n"))
    assert np.array_equal(back.v, bench.train.v) and np.array_equal(back.f, bench.train.f)


def test_unicode_minus_signs_in_a_csv_are_minus_signs(tmp_path, bench):
    text = sweep_csv_text(Sweep(-bench.train.v, -bench.train.f))
    back = read_sweep_csv(_csv(tmp_path, text.replace("-", "\u2212")))
    assert np.array_equal(back.v, -bench.train.v) and np.array_equal(back.f, -bench.train.f)


#: (factor of v, factor of f): units 1e15 apart, within the 1e-30..1e30 the loader accepts.
UNIT_SCALES = [(1e-15, 1e-15), (1.0, 1e-15), (1e15, 1e15), (1e-15, 1.0)]


@pytest.mark.parametrize("sv, sf", UNIT_SCALES, ids=[f"v*{a:g},f*{b:g}" for a, b in UNIT_SCALES])
def test_the_training_set_does_not_depend_on_the_units(bench, sv, sf):
    # B by least squares on an unscaled [1, v] design and an absolute noise floor of 1e-12 N in
    # the vs_max estimate broke a sweep in other units (B = 1.5e-30 or 159 N s/m for 58)
    a = prepare(bench.train)
    b = prepare(Sweep(sv * bench.train.v, sf * bench.train.f))
    # the scaled rows differ from the exact ones by one rounding (1.1e-16); each figure below is
    # a sum, a median or a well-conditioned solve of them, so a few roundings at most
    assert b.v_sat == pytest.approx(sv * a.v_sat, rel=1e-13)
    assert b.viscous == pytest.approx(sf / sv * a.viscous, rel=1e-12)
    assert b.scaling.k_out == pytest.approx(a.scaling.k_out / sf, rel=1e-13)
    np.testing.assert_allclose(b.x, a.x, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(b.t, a.t, rtol=1e-12, atol=1e-13)


def test_training_in_other_units_gives_the_same_model_up_to_the_scale(bench):
    from fricgen.fit import default_estimator
    from fricgen.model import FrictionModel
    v = np.linspace(-0.2, 0.2, 401)
    reference = FrictionModel.fit(prepare(bench.train), default_estimator(0)).force(v)
    for sv, sf in ((1e-15, 1e-15), (1e15, 1e15)):
        model = FrictionModel.fit(prepare(Sweep(sv * bench.train.v, sf * bench.train.f)), default_estimator(0))
        # the training sets agree within 1e-12 (above); the fits' solves amplify that by at most
        # their condition numbers (cond(H^T H) < 1e8 by the parity bound), so 1e-8 of the largest
        # force, where a unit-dependent step (another vs_max, B or choice) moves it by 1e-3 or more
        np.testing.assert_allclose(model.force(sv * v) / sf, reference, rtol=0,
                                   atol=1e-8 * np.max(np.abs(reference)))


def test_noise_free_high_speed_rows_lose_none_but_a_spike():
    """On exact data the Stribeck remainder bends the high-speed rows off the line by far less
    than any gross outlier (7e-4 N here); the MAD alone is then ~0 and named those rows
    outliers (with 5 rows: 'only 4 of 5 rows lie on a line'). A 1 N spike is still dropped."""
    v = np.linspace(0.03, 0.1, 50)
    f = 8.0 + 6.0 * np.exp(-(v / 0.01) ** 2) + 60.0 * v
    for rows in (slice(None), slice(0, 50, 12)):
        B, _, rejected = identify_viscous(Sweep(v[rows], f[rows]))
        assert rejected == 0 and B == pytest.approx(60.0, rel=1e-3)
    spiked = f.copy()
    spiked[20] += 1.0
    assert identify_viscous(Sweep(v, spiked))[2] == 1


def test_a_short_coulomb_viscous_sweep_is_fitted_not_refused():
    """60 clean rows of f = 2 + 15 v (no Stribeck drop): the old estimate put vs_max so high that
    13 rows were left below v_sat and train refused; every candidate now leaves MIN_ROWS."""
    v = np.arange(1, 61) / 300
    dataset = prepare(Sweep(v, 2 + 15 * v))
    assert dataset.n_rows >= 20
    assert dataset.viscous == pytest.approx(15.0, rel=0.05)


def test_an_underflowed_dictionary_column_gets_no_weight_and_no_overflow():
    """A Stribeck velocity far below every speed leaves a column of denormals: it is left out
    (coefficient 0), the fit of the others is the same, and nothing overflows."""
    import warnings
    from fricgen.data.stribeck_range import _nonnegative_fit
    rng = np.random.default_rng(0)
    A = np.column_stack([np.ones(50), rng.uniform(0.1, 1.0, 50), np.full(50, 1e-310)])
    f = 2.0 + 3.0 * A[:, 1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coef = _nonnegative_fit(A, f)
    assert coef[2] == 0.0 and np.allclose(coef[:2], [2.0, 3.0])
    np.testing.assert_array_equal(coef[:2], _nonnegative_fit(A[:, :2], f))


PREAMBLE = "Oscilloscope export\nDevice;Drive 3\nSample time;0,5 ms\n\n"


def _dialect(text, sep, decimal_comma, preamble):
    """``text`` (a ','-separated CSV with '.' decimals) written as a drive's export."""
    lines = [line.replace(".", ",") if decimal_comma else line for line in
             (line.replace(",", sep) for line in text.splitlines())]
    return (PREAMBLE if preamble else "") + "\n".join(lines) + "\n"


@pytest.mark.parametrize("preamble", [False, True], ids=["header first", "preamble"])
@pytest.mark.parametrize("sep, decimal_comma", [(",", False), (";", False), ("\t", False),
                                                (";", True), ("\t", True), ("  ", False)],
                         ids=["comma", "semicolon", "tab", "semicolon decimal comma",
                              "tab decimal comma", "whitespace"])
def test_a_drive_export_reads_as_the_plain_csv(tmp_path, bench, sep, decimal_comma, preamble):
    text = _dialect(sweep_csv_text(bench.train), sep, decimal_comma, preamble)
    back = read_sweep_csv(_csv(tmp_path, text))
    assert np.array_equal(back.v, bench.train.v) and np.array_equal(back.f, bench.train.f)


def test_a_header_that_does_not_split_names_the_delimiter(tmp_path, bench):
    from fricgen.data.table import read_table_csv
    path = _csv(tmp_path, _dialect(sweep_csv_text(bench.train), ";", True, False))
    with pytest.raises(DataError, match=r"does not split at ','.*--delimiter"):
        read_table_csv(path, ["v", "f"], delimiter=",")
    forced = read_table_csv(path, ["v", "f"], delimiter=";", decimal_comma=True)
    assert np.array_equal(forced["v"], bench.train.v)


def test_a_drive_logs_status_column_of_text_is_left_out_of_training(tmp_path, capsys):
    """A status column (text) beside the quantities is no reason to refuse the file: the model
    is the one trained without it."""
    from fricgen.cli import main
    speeds = np.geomspace(0.01, 1.0, 8)
    v = np.concatenate([speeds, -speeds])
    f = np.sign(v) * (0.3 + 0.05 * np.abs(v))
    plain, status = tmp_path / "plain.csv", tmp_path / "status.csv"
    plain.write_text("v,f\n" + "".join(f"{a:.17g},{b:.17g}\n" for a, b in zip(v, f)))
    status.write_text("v,f,status\n" + "".join(f"{a:.17g},{b:.17g},OK\n" for a, b in zip(v, f)))
    for path in (plain, status):
        assert main(["train", str(path), "-o", str(path.with_suffix(".json"))]) == 0
    models = [json.loads(p.with_suffix(".json").read_text()) for p in (plain, status)]
    assert models[0]["model_hash"] == models[1]["model_hash"]
