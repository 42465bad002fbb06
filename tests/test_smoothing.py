"""The Savitzky-Golay smoothing of the inverse dynamics [C1] in time linear in the log:
the FFT path equals ``savgol_filter``, and the window chosen is the one the direct filter chooses."""
import numpy as np
import pytest
from scipy.signal import savgol_coeffs, savgol_filter

from fricgen import _progress
from fricgen.data import inverse_dynamics as idm
from fricgen.data import smoothing
from fricgen.data.inverse_dynamics import identify_friction
from fricgen.data.smoothing import (FFT_WINDOW, between_edges, MAX_WINDOW_FRACTION, MIN_WINDOW, POLYORDER,
                                    WINDOW_RATIO, candidate_windows, choose_window, smooth)
from fricgen.friction import preset

#: Rounding of an FFT convolution against the direct sum, relative to the signal's scale: about
#: 1e-14 measured; 1e-9 leaves room for any FFT library and still tells a wrong kernel or edge.
EQUAL = 1e-9


def _log(n=30000, ts=1e-3, force_noise=2.0, seed=0):
    """A back-and-forth move at 1 kHz (0.2 m/s peak, one cycle per 6 s) on a 4 kg axis with the
    paper's friction, the force noisy enough for a window beyond ``FFT_WINDOW``."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * ts
    v = 0.2 * np.sin(2 * np.pi * t / 6.0)
    a = 0.2 * 2 * np.pi / 6.0 * np.cos(2 * np.pi * t / 6.0)
    force = np.sign(v) * preset("paper3")(np.abs(v)) + 4.0 * a
    return t, v + 5e-4 * rng.standard_normal(n), force + force_noise * rng.standard_normal(n)


def _direct_choice(force, rows, mass, v_noise, ts):
    """``choose_window`` as it was before the FFT path: ``savgol_filter`` for every window."""
    windows = candidate_windows(rows.size)
    scores = []
    for w in windows:
        residual = (force - savgol_filter(force, w, POLYORDER))[rows]
        h0 = savgol_coeffs(w, POLYORDER)[w // 2]
        noise = np.linalg.norm(savgol_coeffs(w, POLYORDER, deriv=1, delta=ts))
        scores.append(np.mean(residual ** 2) / (1 - h0) ** 2 + (mass * v_noise * noise) ** 2)
    return windows[int(np.argmin(scores))], np.array(scores)


@pytest.mark.parametrize("window", [FFT_WINDOW - 1, FFT_WINDOW + 1, 101, 1001, 29999])
@pytest.mark.parametrize("deriv, delta", [(0, 1.0), (1, 1e-3)])
def test_fft_smoothing_equals_savgol_filter_including_the_ends(window, deriv, delta):
    _, v, force = _log()
    for signal in (v, force):
        direct = savgol_filter(signal, window, POLYORDER, deriv=deriv, delta=delta)
        fast = smooth(signal, window, deriv, delta)
        scale = np.max(np.abs(direct))
        assert np.max(np.abs(fast - direct)) <= EQUAL * scale
        half = window // 2                                  # the polynomial-fitted ends alone
        assert np.max(np.abs(fast[:half] - direct[:half])) <= EQUAL * scale
        assert np.max(np.abs(fast[-half:] - direct[-half:])) <= EQUAL * scale


def test_short_windows_are_savgol_filter_bit_for_bit():
    _, v, _ = _log(n=5000)
    np.testing.assert_array_equal(smooth(v, FFT_WINDOW - 1, 1, 1e-3),
                                  savgol_filter(v, FFT_WINDOW - 1, POLYORDER, deriv=1, delta=1e-3))


@pytest.mark.parametrize("force_noise", [0.05, 2.0, 8.0])
def test_the_window_chosen_is_the_direct_filters_choice(force_noise):
    t, v, force = _log(force_noise=force_noise)
    noise = idm.velocity_noise(v)
    rows = np.abs(savgol_filter(v, MIN_WINDOW, POLYORDER)) > idm.MOVING_SIGMAS * noise
    expected, scores = _direct_choice(force, rows, 4.0, noise, 1e-3)
    assert choose_window(force, rows, 4.0, smoothing.VelocityNoise(noise, 0.0, 1e-3)) == expected
    fast = [smoothing.gcv_score(force, w, rows) + (4.0 * noise * smoothing.derivative_noise(w, 1e-3)) ** 2
            for w in candidate_windows(rows.size)]
    np.testing.assert_allclose(fast, scores, rtol=EQUAL)
    beyond = np.flatnonzero(scores > smoothing.STOP_FACTOR * np.minimum.accumulate(scores))
    if beyond.size:                                         # where the search stops: safely
        assert scores[beyond[0]:].min() > scores[:beyond[0]].min()
    if force_noise == 8.0:
        assert expected > FFT_WINDOW                        # the FFT path made this choice


def test_candidate_windows_are_odd_geometric_and_within_the_fraction():
    windows = candidate_windows(200000)
    assert windows[0] == MIN_WINDOW and all(w % 2 == 1 for w in windows)
    assert windows[-1] <= MAX_WINDOW_FRACTION * 200000 < windows[-1] * WINDOW_RATIO + 2
    ratios = np.diff(windows) / np.array(windows[:-1])
    assert np.all(ratios > 0) and np.all(ratios < WINDOW_RATIO + 2 / MIN_WINDOW)
    assert candidate_windows(1000) == [7, 9, 11, 13, 17, 21, 27, 33, 41]   # up to 5 % of 1000
    assert candidate_windows(10) == [MIN_WINDOW]            # never fewer than the smallest


def test_progress_goes_to_the_callback_not_to_stderr(monkeypatch, capsys):
    t, v, force = _log(n=20000)
    heard = []
    monkeypatch.setattr(_progress, "PROGRESS_SECONDS", 0.0)      # report after every window
    quiet = identify_friction(t, force, 4.0, v=v)
    told = identify_friction(t, force, 4.0, v=v, progress=heard.append)
    assert told.window == quiet.window
    assert 1 < len(heard) < len(candidate_windows(t.size)) and "smoothing window" in heard[0]
    assert capsys.readouterr() == ("", "")


def test_a_position_in_counts_read_between_its_edges_follows_the_motion():
    """A move with a ripple logged as floored counts (about 30 rows per count): read between
    its edges the position is within a tenth of a count of the motion less half a count (the
    floor's mean), where the counts stray by half a count; the acceleration smoothed over 30 ms
    is five times closer to the ripple's."""
    t = np.arange(0.0, 1.0, 1e-4)
    motion = 300.0 * t + 2.0 * np.sin(2 * np.pi * 5 * t) + 0.3           # in counts
    counts = np.floor(motion)
    inner = slice(1000, -1000)
    read = between_edges(t, counts)
    assert np.max(np.abs(read - (motion - 0.5))[inner]) < 0.1
    assert np.max(np.abs(counts - (motion - 0.5))[inner]) > 0.45
    ripple_a = -2.0 * (2 * np.pi * 5) ** 2 * np.sin(2 * np.pi * 5 * t)

    def rms(x):
        return float(np.sqrt(np.mean((smooth(x, 301, 2, 1e-4) - ripple_a)[inner] ** 2)))
    assert 5 * rms(read) < rms(counts)


def test_a_position_that_changes_at_every_row_is_read_as_it_is_but_for_a_light_smoothing():
    t = np.arange(200) * 1e-3
    x = np.cumsum(np.random.default_rng(0).uniform(0.5, 1.5, t.size))
    assert np.allclose(between_edges(t, x)[1:-1], (x[:-2] + 2 * x[1:-1] + x[2:]) / 4)
    assert np.array_equal(between_edges(t, np.full(t.size, 3.0)), np.full(t.size, 3.0))


def test_a_counts_rounding_weighs_less_in_a_long_window_than_white_noise_of_its_size():
    """The rounding of a position in counts (q / sqrt 12 on x) and white noise on v of the same
    per-sample size (q / (ts sqrt 24)) leave the same noise in one sample of v; smoothed over a
    long window, the differenced rounding leaves a fraction of it, in v and in dv/dt."""
    q, ts = 1e-5, 2.5e-4
    counts = smoothing.VelocityNoise(0.0, q / np.sqrt(12.0), ts)
    white = smoothing.VelocityNoise(q / (ts * np.sqrt(24.0)), 0.0, ts)
    assert counts.per_sample() == pytest.approx(white.per_sample())
    rng = np.random.default_rng(1000)
    rounding = rng.uniform(-q / 2, q / 2, 200_000)
    v = np.gradient(rounding, ts)
    for window in (31, 485):
        assert np.std(smooth(v, window)[window:-window]) == pytest.approx(counts.smoothed(window), rel=0.05)
        assert np.std(smooth(v, window, 1, ts)[window:-window]) == pytest.approx(counts.derivative(window), rel=0.05)
    assert counts.smoothed(485) < 0.1 * white.smoothed(485)
    assert counts.derivative(485) < 0.2 * white.derivative(485)
