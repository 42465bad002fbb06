"""The cogging map's identification on calibrations written here, without a drive's loop: a
period the travel shows twice, harmonics beyond 512, a position in counts
(``fricgen.fit.identify_cogging``)."""
import re

import numpy as np
import pytest

from fricgen.cli import main
from fricgen.errors import DataError
from fricgen.fit.cogging import identify_cogging
from fricgen.sim.servo_axis import TWO_PI


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_period_seen_twice_in_the_travel_is_placed_by_all_its_harmonics(seed):
    """A linear motor whose cogging repeats every pole pitch (32 mm; harmonics 1, 2, 6, 12) over
    a calibration of two pitches each way: one sinusoid's peak placed the period 0.1-0.5 % off
    (the map then 3-11 % off); the series of its harmonics places it within 0.02 %."""
    rng = np.random.default_rng(seed)
    pitch, speed, rate = 0.032, 0.01, 4000.0
    t = np.arange(0, 4 * 2 * pitch / speed, 1 / rate)
    x = np.round(speed * (2 * pitch / speed - np.abs(t - 2 * pitch / speed)) / 1e-6) * 1e-6
    h, amp, phase = np.array([1, 2, 6, 12]), np.array([4.0, 1.5, 2.0, 0.8]), rng.uniform(0, TWO_PI, 4)

    def cogging(u):
        return (amp[:, None] * np.sin(np.outer(h, TWO_PI * u / pitch) + phase[:, None])).sum(axis=0)
    v = np.gradient(x, t)
    f = cogging(x) + 20.0 * np.sign(v) + 300.0 * v + 0.3 * rng.standard_normal(t.size)
    fit = identify_cogging(t, x, f, None, inertia=0.0)
    assert fit.period == pytest.approx(pitch, rel=2e-4)
    assert 0 < fit.period_se < 2e-4 * pitch and abs(fit.period - pitch) < 4 * fit.period_se
    u = np.linspace(0, pitch, 2000)
    assert np.sqrt(np.mean((fit.map.force(u) - cogging(u)) ** 2)) < 0.01 * np.std(cogging(u))


def _turns(harmonics, amplitudes, bits, seed=0, counts=False):
    """Two turns each way at 1 rad/s, 8 kHz, the position in steps of a ``bits`` encoder (in
    counts where ``counts``), a cogging of ``harmonics`` per turn, Coulomb friction, noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, 8 * np.pi, 1 / 8000.0)
    step = TWO_PI / 2 ** bits
    x = np.round((2 * TWO_PI - np.abs(t - 2 * TWO_PI)) / step) * step
    phase = rng.uniform(0, TWO_PI, len(harmonics))

    def cogging(u):
        return sum(a * np.sin(h * u + p) for h, a, p in zip(harmonics, amplitudes, phase))
    f = cogging(x) + 0.02 * np.sign(np.gradient(x, t)) + 1e-3 * rng.standard_normal(t.size)
    return t, (np.round(x / step) if counts else x), f, cogging


def test_harmonics_beyond_512_are_screened():
    """A 36-slot, 32-pole motor cogs 288 times a turn: its second harmonic (576) was beyond the
    512 screened and left out silently (a map 20-35 % off); on a 14-bit encoder it is found."""
    t, x, f, cogging = _turns((288, 576), (0.01, 0.004), bits=14)
    fit = identify_cogging(t, x, f, period=TWO_PI, inertia=0.0)
    assert fit.highest_harmonic > 576 and fit.map.harmonics == (288, 576)
    u = np.linspace(0, TWO_PI, 1 << 16)
    assert np.sqrt(np.mean((fit.map.force(u) - cogging(u)) ** 2)) < 0.05 * np.std(cogging(u))


def test_a_position_in_counts_is_named_not_blamed_on_the_speed():
    """x in encoder counts read as rad: 6 steps a turn. The refusal asks whether x is in counts
    (it said 'move slower or log faster', which no move fixes) and says the size of a count (a
    --pitch of a whole turn in counts, which its advice on a short period read as, is refused
    as longer than a turn)."""
    t, x, f, _ = _turns((24,), (0.01,), bits=12, counts=True)
    with pytest.raises(DataError, match="is x in encoder counts or another unit") as refused:
        identify_cogging(t, x, f, period=TWO_PI, inertia=0.0)
    assert "2 pi over the counts per turn" in str(refused.value)
    assert "a period shorter than a turn" in str(refused.value)


def test_a_nan_or_a_pause_in_the_calibration_is_named():
    """A NaN force is named by its column and row (it read as a move covering 0 % of the
    period); a pause in the time stamps names its first gap and says a map needs none."""
    t = np.arange(0, 8, 1e-3)
    x = 2 * TWO_PI * (1 - np.abs(1 - t / 4))
    f = 0.05 * np.sin(24 * x) + 0.02 * np.sign(np.gradient(x, t))
    bad = f.copy()
    bad[4000] = np.nan
    with pytest.raises(DataError, match="column 'force' holds NaN .* data row 4001"):
        identify_cogging(t, x, bad, TWO_PI)
    paused = t + 0.5 * (t >= 2) + 0.5 * (t >= 6)
    with pytest.raises(DataError, match=r"between data rows 2000 and 2001 \(the first of 2 such "
                                        r"steps\).*without pauses"):
        identify_cogging(paused, x, f, TWO_PI)


def _linear_move(rng, cogging, ripple=0.0):
    """Two pole pitches (32 mm) each way at 10 mm/s, 4 kHz, a 1 um encoder; the force: the
    cogging of x, friction, noise, and ``ripple``: a loop's ripple 6 samples long."""
    pitch, speed, rate = 0.032, 0.01, 4000.0
    t = np.arange(0, 4 * 2 * pitch / speed, 1 / rate)
    x = np.round(speed * (2 * pitch / speed - np.abs(t - 2 * pitch / speed)) / 1e-6) * 1e-6
    v = np.gradient(x, t)
    f = cogging(x) + 5.0 * np.sign(v) + 20.0 * v + ripple * np.sin(2 * np.pi * rate / 6 * t) \
        + 0.05 * rng.standard_normal(t.size)
    return t, x, f


@pytest.mark.parametrize("seed", [0, 1])
def test_a_strong_harmonic_of_the_pitch_is_placed_as_a_harmonic(seed):
    """The 6th harmonic of the pole pitch stronger than the 1st: the period found was a sixth of
    the pitch, the map 37 % off; the strongest peak's sub-multiples find the pitch."""
    rng = np.random.default_rng(seed)
    phase = rng.uniform(0, TWO_PI, 2)

    def cogging(u):
        return 0.8 * np.sin(TWO_PI * u / 0.032 + phase[0]) + 2.0 * np.sin(6 * TWO_PI * u / 0.032 + phase[1])
    fit = identify_cogging(*_linear_move(rng, cogging), None, inertia=0.0)
    assert fit.period == pytest.approx(0.032, rel=1e-3)
    u = np.linspace(0, 0.032, 2000)
    assert np.sqrt(np.mean((fit.map.force(u) - cogging(u)) ** 2)) < 0.03 * np.std(cogging(u))


def test_a_linear_log_without_cogging_gets_no_map_not_a_refusal():
    """Without --pitch, a loop's ripple 6 samples long was taken for the period and the log
    refused ("resolves the period too coarsely"); a period the map cannot be built on is no
    candidate, and no harmonic stands above the noise."""
    fit = identify_cogging(*_linear_move(np.random.default_rng(3), lambda u: 0.0 * u, 0.3), None,
                           inertia=0.0)
    assert fit.map is None


def test_a_ripple_at_an_alias_of_the_encoder_is_no_cogging():
    """A drive at 8 kHz reading a 12-bit encoder per 32 mm at 32 mm/s sees its count's error at
    twice the count rate folded by the sample rate, 2 x 4096 - 8000 = 192 Hz (and 384): at a
    steady speed a ripple there repeats along the travel like harmonic 192 (and 384) of the
    pitch, and was a map of them on a motor without cogging. The real harmonic stays."""
    rng = np.random.default_rng(5)
    pitch, speed, rate = 0.032, 0.032, 8000.0
    quantum = pitch / 4096
    t = np.arange(0, 4 * pitch / speed, 1 / rate)
    x = np.round(speed * (2 * pitch / speed - np.abs(t - 2 * pitch / speed)) / quantum) * quantum
    v = np.gradient(x, t)
    f = (8.0 * np.sign(v) + 20.0 * v + 1.2 * np.sin(TWO_PI * 192 * t) + 0.8 * np.sin(TWO_PI * 384 * t + 1)
         + 0.3 * rng.standard_normal(t.size))
    assert identify_cogging(t, x, f, pitch, inertia=0.0).map is None
    assert identify_cogging(t, x, f, None, inertia=0.0).map is None
    cogging = 1.5 * np.sin(TWO_PI * 6 * x / pitch + 0.4)
    fit = identify_cogging(t, x, f + cogging, pitch, inertia=0.0)
    assert fit.map.harmonics == (6,) and fit.map.amplitude[0] == pytest.approx(1.5, rel=0.05)


def test_a_move_that_turns_back_between_its_ends_is_warned_of(tmp_path, capsys):
    """A velocity loop too soft for the cogging lets the axis stall and turn back within the
    move (a trial's soft drive: speeds of 0.2 to 5.7 rad/s at 1 rad/s, its map 99 % off, with no
    word): the map is fitted on the steady rows alone, and train says how much of the travel
    they cover. The steady calibration of the same axis gets no such warning."""
    t, x, f, _ = _turns((12, 24), (0.01, 0.004), bits=16)
    wobble = 0.05 * np.sin(TWO_PI * 5.0 * t)            # 1.57 rad/s at 5 Hz on the 1 rad/s move
    for name, position in (("steady", x), ("wobbling", x + wobble)):
        accel = np.gradient(np.gradient(position, t), t)
        np.savetxt(tmp_path / f"{name}.csv", np.column_stack([t, position, f + 1e-4 * accel]),
                   delimiter=",", header="t,x,force", comments="", fmt="%.10g")
    for name, warned in (("steady", False), ("wobbling", True)):
        assert main(["train", str(tmp_path / f"{name}.csv"), "--cogging", "--rotary",
                     "-o", str(tmp_path / f"{name}.json")]) == 0
        said = re.search(r"the move covers (\d+)% of its travel at a steady speed", capsys.readouterr().err)
        assert (said is not None) == warned
        assert not warned or int(said.group(1)) < 90


def test_a_screen_cut_by_bins_a_direction_left_unvisited_is_warned_of(tmp_path, capsys):
    """A way back 16 times as fast fills a sixteenth of the position bins the way out does: the
    screen stops where that direction leaves bins empty (a trial's soft loop: harmonics above 32,
    its map 38 % off), which the report's body alone had said. The even calibration is not."""
    rng = np.random.default_rng(1000)
    step, rate = TWO_PI / 2 ** 14, 8000.0
    out = np.arange(0, 2 * TWO_PI, 1.0 / rate)
    back = 2 * TWO_PI - np.arange(0, 2 * TWO_PI, 16.0 / rate)
    for name, path in (("even", np.concatenate([out, 2 * TWO_PI - out])),
                       ("uneven", np.concatenate([out, back]))):
        x = np.round(path / step) * step
        t = np.arange(x.size) / rate
        f = (0.01 * np.sin(12 * x + 0.4) + 0.004 * np.sin(24 * x + 1.0)
             + 0.02 * np.sign(np.gradient(x, t)) + 1e-3 * rng.standard_normal(x.size))
        np.savetxt(tmp_path / f"{name}.csv", np.column_stack([t, x, f]), delimiter=",",
                   header="t,x,force", comments="", fmt="%.10g")
        assert main(["train", str(tmp_path / f"{name}.csv"), "--cogging", "--rotary",
                     "-o", str(tmp_path / f"{name}.json")]) == 0
        err = capsys.readouterr().err
        assert ("finer ones left unvisited in a direction: the move stalls" in err) == (name == "uneven")


@pytest.mark.parametrize("harmonic, in_degrees", [(18, True), (1680, True), (29516, False)])
def test_a_wavelength_is_read_in_degrees_only_at_a_harmonic_a_cogging_reaches(harmonic, in_degrees):
    """A rotary calibration with its true inertia given had been refused as 'harmonic 29516 of
    the period if x is in deg': any wavelength falls within 0.01 of a harmonic 2 % of the time.
    A map in degrees has its harmonics at the cogging's numbers, so only those are asked about."""
    from fricgen.training.with_cogging import _in_other_units
    from fricgen.units import units_of
    wavelength = TWO_PI / (harmonic * np.radians(1.0))
    assert bool(_in_other_units(wavelength, TWO_PI, units_of(True))) == in_degrees
