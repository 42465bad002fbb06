"""The cogging map identified from a slow move over the travel (a calibration of two
revolutions each way, or a log of normal operation that covers the period):

    f = J a + c_d + b_d v + C(x) + sgn(v) R(x) + noise,

d the direction of motion: the drive force f is the inertia's, a per-direction Coulomb and
viscous friction, the position force C (cogging, unbalance: ``CoggingMap``) and a friction
that varies along the travel R (a ripple times sgn(v)), kept apart from C because the two
directions see R with opposite signs.

1. Screening: the force less the per-direction friction, averaged in position bins per
   direction (the most bins both directions fill, all but MAX_EMPTY of them: a bin left
   unvisited, where the axis stalled, is interpolated), and its Fourier coefficients up to the
   highest harmonic the bins, the encoder and the sample rate resolve; C's are the mean of the
   two directions', R's half their difference. A harmonic is a candidate when its amplitude
   exceeds the level that noise alone reaches with probability ALPHA over all harmonics tried
   (Rayleigh, the noise level the median amplitude of the harmonics around it), and not at an
   alias of the encoder at the move's steady speed (``encoder_alias``: the drive's own ripple).
2. J (``--mass`` fixes it) from how the two directions differ at the candidates of C: the
   velocity ripple the loop leaves turns its phase with the direction (``_inertia``). Where it
   does not differ beyond its noise, J is undetermined and taken as 0, and the report says so.
3. How many candidates (strongest first) by blocked cross-validation of the time-domain least
   squares with the one-standard-error rule (``effects.fitting.nested_cross_validation``);
   none is an answer: the log has no cogging.
4. The coefficients by least squares on f - J a, their standard errors by the blocked jackknife
   (the residual of a drive's loop is correlated in time; the blocks are long beside that).

Rows of a start or stop by a velocity step (``_not_transient``) are left out first. v and a of a
position in encoder counts come from the position between its count edges
(``data.smoothing.between_edges``); the map is a function of the counts themselves.

BLAS runs on the threads ``fricgen.train`` uses (``_blas``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np
from scipy.ndimage import median_filter, minimum_filter1d, uniform_filter1d

from .._blas import blas_threads, wanted_threads
from ..data.inverse_dynamics import position_quantum
from ..data.motionlog import check_finite, uniform_time
from ..data.smoothing import MIN_WINDOW, between_edges, smooth, steady_rows
from ..effects.fitting import FIT_FOLDS, block_grams, lstsq, nested_cross_validation, refine
from ..errors import DataError
from ..effects.cogging_map import MAX_TERMS, CoggingMap
from .encoder_alias import SPEED_PRECISION, aliased, count_alias
from .position_bins import MIN_BINS, bin_cap, bin_coefficients, filled_bins

#: Family-wise probability that noise alone puts a harmonic among the candidates.
ALPHA = 0.01
#: Highest harmonic screened; harmonics per period the encoder (QUANTA_PER_WAVE counts) and the
#: sample rate (SAMPLES_PER_WAVE samples) must resolve.
MAX_HARMONIC = 1024
QUANTA_PER_WAVE = 6
SAMPLES_PER_WAVE = 6
#: Half-width (harmonics) of the running median that sets the noise level.
NOISE_SPAN = 16
#: The window (s) of the smoothed velocity (rows in motion) and of the acceleration with which
#: the number of harmonics is chosen.
INERTIA_WINDOW = 0.02
#: The acceleration's smoothing window spans at most 1 / A_WINDOW_WAVES of the fastest
#: candidate harmonic's period in time (less smoothing: more noise; more: J a attenuated).
A_WINDOW_WAVES = 3.0
#: J is taken when it exceeds this many of its standard errors.
INERTIA_Z = 3.0
#: Position bins of the periodogram that finds the period, and the fewest periods it must see.
FUNDAMENTAL_BINS = 1 << 16
FUNDAMENTAL_PERIODS = 2
#: The period found is refined with this many of its harmonics, on at most PERIOD_ROWS rows.
PERIOD_HARMONICS = 16
PERIOD_ROWS = 20_000
#: Periods the travel must hold for a wavelength to be checked for a wrong period (longer ones
#: are not told from the friction's slow drifts along the travel).
UNEXPLAINED_PERIODS = 8
#: ... and its amplitude at least this share of the map's strongest harmonic (the encoder's
#: count, aliased by the log's sample rate, leaves weaker lines in a calibration).
UNEXPLAINED_SHARE = 0.25
#: How ``CoggingFit.screened_by`` names the sample rate as what set the highest harmonic, and
#: what it says of bins a direction left unvisited.
SAMPLE_RATE_LIMIT = "the sample rate"
UNVISITED = "finer ones left unvisited in a direction"
#: Rows whose force less the friction strays farther than this many robust standard deviations
#: are left out (``_not_transient``).
TRANSIENT_SIGMAS = 10.0
#: The robust relative spread of the speed beyond which the encoder's aliases form no line (no
#: constant speed to place them): a speed that varies with the position, as the cogging's
#: ripple makes it (0.09 on a 12-bit axis at 3 rad/s), keeps them lines with sidebands.
STEADY_SPREAD = 0.25


@dataclass(frozen=True)
class CoggingFit:
    """What ``identify_cogging`` found.

    Parameters
    ----------
    map : CoggingMap or None
        The position force (cogging, unbalance); None when no harmonic stands above the noise.
    friction : CoggingMap or None
        The friction that varies along the travel (times sgn(v)), likewise.
    inertia : float
        The inertia (mass) whose J a was taken out of the force.
    inertia_source : str
        "given", "identified" (from the two directions' ripple) or "undetermined" (then 0: the
        map holds the inertia's ripple too).
    coulomb_viscous : tuple of float
        c+, b+, c-, b-: the friction per direction, c_d + b_d v.
    highest_harmonic : int
        The highest harmonic screened (what the encoder and the sample rate resolve).
    residual_rms : float
        The RMS of the fit's residual.
    rows : int
        The rows in motion that were fitted.
    period : float, optional
        The period fitted (given, or found in the data).
    period_se : float, optional
        The standard error of a period found in the data; None for a period given.
    unexplained_wavelength : float, optional
        The wavelength of a position-periodic force the residual still holds that no harmonic
        of the period can (a wrong period given); None when there is none.
    screened_by : str, optional
        What set ``highest_harmonic`` (the sample rate at the move's speed, the encoder, the
        position bins a direction visited, or fricgen's limit).
    steady_travel : float, optional
        The share of the log's travel covered by the rows in motion at a steady direction and
        speed (``_moving``), the rows the map is fitted on; the rest stalls or turns back.
    speeds : tuple of float, optional
        The 5th, 50th and 95th percentiles of |v| over those rows (0 where not measured).
    count_alias : int, optional
        Where the encoder's count rate at the move's steady speed exceeds half the log's rate,
        the harmonic of the period at which the log folds it, if the map screens that far
        (``count_alias``); else None.

    Examples
    --------
    >>> fit = CoggingFit(None, None, 0.0, "undetermined", (0.02, 0.0, -0.02, 0.0), 64, 0.01, 4000)
    >>> fit.map is None
    True
    """

    map: Optional[CoggingMap]
    friction: Optional[CoggingMap]
    inertia: float
    inertia_source: str
    coulomb_viscous: Tuple[float, float, float, float]
    highest_harmonic: int
    residual_rms: float
    rows: int
    period: Optional[float] = None
    period_se: Optional[float] = None
    unexplained_wavelength: Optional[float] = None
    screened_by: str = ""
    steady_travel: float = 1.0
    speeds: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    count_alias: Optional[int] = None


def _odd(n: float) -> int:
    return max(MIN_WINDOW, int(n) | 1)


def _less_nuisance(f: np.ndarray, nuisance: np.ndarray) -> np.ndarray:
    """f less its least-squares fit by the friction columns."""
    return f - nuisance @ lstsq(nuisance, f)[0]


def _nuisance(v: np.ndarray) -> np.ndarray:
    """Columns of the per-direction Coulomb and viscous friction: [v>0], v [v>0], [v<0], v [v<0]."""
    pos, neg = (v > 0).astype(float), (v < 0).astype(float)
    return np.column_stack([pos, v * pos, neg, v * neg])


def _moving(v: np.ndarray, window: int) -> np.ndarray:
    """Rows where the axis moves in one direction over the whole window, faster than a fifth of
    its typical speed (``steady_rows``)."""
    return steady_rows(v, np.abs(v) > 0.2 * np.percentile(np.abs(v), 90), window)


def _travel_share(x: np.ndarray, rows: np.ndarray) -> float:
    """The share of the travel (the sum of |dx|) covered from the given rows."""
    step = np.abs(np.diff(x))
    total = float(step.sum())
    return float(step[rows[:-1]].sum()) / total if total > 0 else 1.0


def _not_transient(r: np.ndarray) -> np.ndarray:
    """The rows whose force less the friction lies within TRANSIENT_SIGMAS robust standard
    deviations (1.4826 median absolute deviations) of its median: the few rows of a start or
    stop by a velocity step, whose force is many times the cogging's, would otherwise spread
    over every harmonic's bin average and hide the cogging."""
    deviation = np.abs(r - np.median(r))
    return deviation <= TRANSIENT_SIGMAS * 1.4826 * max(float(np.median(deviation)), 1e-300)


def _inertia(x, r, a, sign, period, bins, harmonics) -> Optional[float]:
    """J from how the two directions differ at the harmonics of the position force: a force
    C(x) the loop only partly rejects leaves a velocity ripple whose phase turns with the
    direction of motion (the loop's response at +w and at -w are conjugate), so at each of those
    harmonics F+ - F- = J (A+ - A-) (F, A the per-direction coefficients of the force and of the
    acceleration; r the force less the friction columns). Least squares over the harmonics; None
    when the directions' accelerations do not differ beyond their noise (the log does not
    determine J)."""
    h = np.asarray(sorted(harmonics), dtype=float)
    if h.size == 0:
        return None
    (fpa, fpb), (fna, fnb) = bin_coefficients(x, r, sign, period, bins, h)
    (apa, apb), (ana, anb) = bin_coefficients(x, a - a.mean(), sign, period, bins, h)
    dF = np.concatenate([fpa - fna, fpb - fnb])
    dA = np.concatenate([apa - ana, apb - anb])
    norm = float(dA @ dA)
    if norm <= 0:
        return None
    inertia = float(dA @ dF) / norm
    residual = dF - inertia * dA
    se = np.sqrt(float(residual @ residual) / max(dF.size - 1, 1) / norm)
    return inertia if inertia > 0 and inertia > INERTIA_Z * se else None


def _candidates(a, b, span):
    """Indices of the harmonics whose amplitude exceeds the noise level's ALPHA threshold, and
    every harmonic's z (amplitude over the noise scale: the median amplitude of the ``span``
    harmonics on each side, itself left out, as Rayleigh's median sigma sqrt(2 ln 2))."""
    amp = np.hypot(a, b)
    n = amp.size
    scale = np.empty(n)
    for j in range(n):
        lo, hi = max(0, min(j - span, n - 1 - 2 * span)), min(n, max(j + span, 2 * span) + 1)
        around = np.delete(amp[lo:hi], j - lo) if hi - lo > 1 else amp
        scale[j] = np.median(around) / np.sqrt(2 * np.log(2))
    z = amp / np.maximum(scale, 1e-300)
    threshold = np.sqrt(2 * np.log(n / ALPHA))
    return np.flatnonzero(z > threshold), z


def _waves(x, k, terms, sign):
    """The time-domain columns of the terms: (h, signed) -> sin(h k x), cos(h k x) (times sgn)."""
    cols = []
    for h, signed in terms:
        w = np.column_stack([np.sin(h * k * x), np.cos(h * k * x)])
        cols.append(w * sign[:, None] if signed else w)
    return np.hstack(cols) if cols else np.empty((x.size, 0))


def _jackknife_se(design, target, folds=FIT_FOLDS):
    """The blocked jackknife standard error of each least-squares coefficient (each fold's fit
    from the Gram matrices less its block's)."""
    grams = block_grams(design, target, folds)
    g_all, b_all = sum(g[0] for g in grams), sum(g[1] for g in grams)
    coefs = np.array([np.linalg.lstsq(g_all - g, b_all - b, rcond=None)[0] for g, b, _, _ in grams])
    return np.sqrt((folds - 1) / folds * np.sum((coefs - coefs.mean(axis=0)) ** 2, axis=0))


def _screen(x, r, sign, period, speed, ts, quantum, pace=None):
    """The candidate terms (h, signed), strongest first, the highest harmonic screened, what
    set it (``_screen_limit``) and the position bins per period (``filled_bins``): the
    harmonics of the bin means of r (the force less the friction columns) per direction whose
    amplitude noise alone reaches with probability below ALPHA (``_candidates``), less those at
    an alias of the encoder (``encoder_alias.aliased``, at the steady speed ``pace``)."""
    samples = period / (speed * ts)                 # samples per period in each pass
    cells = period / quantum if quantum > 0 else np.inf
    if samples < 2 * MIN_BINS and samples <= cells:
        raise DataError(f"the log resolves the cogging's period too coarsely ({samples:.0f} samples "
                        f"per period at {speed:.3g} per s, need {2 * MIN_BINS}): move slower or log "
                        "faster")
    if cells < 2 * MIN_BINS:
        raise DataError(f"the position's step {quantum:.3g} resolves the cogging's period "
                        f"{period:.6g} too coarsely ({cells:.0f} steps, need {2 * MIN_BINS}): is x in "
                        "encoder counts or another unit (--scale x= the size of its unit: 2 pi over "
                        "the counts per turn)? With x as fine as the encoder and a period shorter "
                        "than a turn, give a whole turn as --pitch: the period's harmonics come from it")
    bins = filled_bins(x, sign, period, min(samples, cells) / 2)
    # harmonics up to a quarter of the bins (their averaging attenuates those by at most 10 %)
    highest = int(min(MAX_HARMONIC, bins // 4, samples / SAMPLES_PER_WAVE, cells / QUANTA_PER_WAVE))
    harmonics = np.arange(1, max(highest, 1) + 1)
    (ap, bp), (an, bn) = bin_coefficients(x, r, sign, period, bins, harmonics)
    span = min(NOISE_SPAN, max(highest // 2, 1))
    ranked = []
    for signed, (sa, sb) in ((False, ((ap + an) / 2, (bp + bn) / 2)), (True, ((ap - an) / 2, (bp - bn) / 2))):
        chosen, z = _candidates(sa, sb, span)
        ranked += [(float(z[j]), int(harmonics[j]), signed) for j in chosen]
    ranked.sort(reverse=True)
    kept = []    # strongest first: a term at a sideband of a stronger one's is none, unless a
    for term in ranked:          # multiple of one (the alias may fall on the cogging's harmonics)
        h = term[1]
        carriers = [] if any(h % k == 0 for _, k, _ in kept if k > 1) else [k for _, k, _ in kept]
        if not aliased(2 * np.pi * h / period, quantum, pace, ts, 2 * np.pi / period,
                       [2 * np.pi * k / period for k in carriers]):
            kept.append(term)
    ranked = kept
    limit = _screen_limit(highest, bins, samples, cells)
    return [(h, s) for _, h, s in ranked[:MAX_TERMS]], int(harmonics[-1]), limit, bins


def _screen_limit(highest, bins, samples, cells) -> str:
    """What set the highest harmonic screened: MAX_HARMONIC, or the position bins (a quarter of
    them), themselves set by the samples per period of a pass (the sample rate and the speed),
    by the encoder's counts per period, or by bins a direction left unvisited."""
    if highest >= MAX_HARMONIC:
        return f"fricgen's limit of {MAX_HARMONIC}"
    if bins < bin_cap(min(samples, cells) / 2):
        return f"{bins} position bins, {UNVISITED}"
    if samples <= cells:
        return (f"{SAMPLE_RATE_LIMIT}: {samples:.0f} samples per period at this speed; a slower move "
                "or a faster log screens more")
    return f"the encoder: {cells:.0f} counts per period"


def _travel_spectrum(x, r, speed, ts, quantum, pace=None):
    """The position periodogram of r: its bin means over the whole travel (both directions
    together), zero-padded FFT; the wavenumbers, the amplitudes, the usable ones (at least
    FUNDAMENTAL_PERIODS periods in the travel, resolved by the encoder and the sample rate, at
    no alias of the encoder: ``encoder_alias.aliased``) and the FFT's wavenumber spacing."""
    travel = float(np.ptp(x))
    step = max(quantum, travel / FUNDAMENTAL_BINS)
    n = int(travel / step) + 1
    idx = np.minimum(((x - x.min()) / step).astype(int), n - 1)
    counts = np.bincount(idx, minlength=n)
    means = np.bincount(idx, weights=r, minlength=n) / np.maximum(counts, 1)
    means = np.where(counts > 0, means - means[counts > 0].mean(), 0.0)
    spectrum = np.abs(np.fft.rfft(means, 4 * n))
    k = 2 * np.pi * np.fft.rfftfreq(4 * n, step)
    finest = min(2 * np.pi / (QUANTA_PER_WAVE * max(quantum, step)), 2 * np.pi / (SAMPLES_PER_WAVE * speed * ts))
    usable = (k >= 2 * np.pi * FUNDAMENTAL_PERIODS / travel) & (k <= finest)
    usable &= ~aliased(k, quantum, pace, ts, 2 * np.pi / travel)
    return k, spectrum, usable, 2 * np.pi / (4 * n * step)


def _peak_z(spectrum: np.ndarray, usable: np.ndarray) -> Tuple[np.ndarray, float]:
    """Each wavenumber's periodogram amplitude over the noise around it (a drive's noise is not
    white: the running median over NOISE_SPAN Rayleigh resolutions, 4 FFT points each, on each
    side), 0 where not ``usable``; and the level noise alone reaches with probability ALPHA over
    the usable ones (Rayleigh)."""
    local = median_filter(spectrum, size=8 * NOISE_SPAN + 1, mode="nearest") / np.sqrt(2 * np.log(2))
    z = np.where(usable, spectrum / np.maximum(local, 1e-300), 0.0)
    return z, float(np.sqrt(2 * np.log(max(usable.sum() / 4, 1.0) / ALPHA)))


def _fundamental(x, f, nuisance, speed, ts, quantum, pace=None) -> Optional[Tuple[float, float]]:
    """The map's period found in the data: the wavelength of the strongest peak of the position
    periodogram (``_travel_spectrum``), refined (``_refined_peak``) as one sinusoid, then as the
    series of its first PERIOD_HARMONICS harmonics; None where no peak stands above the noise
    (``_peak_z``). Only periods the map can be built on are candidates: 2 MIN_BINS samples and
    counts each (a linear log without cogging had its loop's 16 um ripple, 6 samples long, taken
    for the period, and was refused). Content at a longer period (a once-per-pole-pair or
    once-per-turn term) needs the period given. Returned with its standard error (the blocked
    jackknife of the last refinement over FIT_FOLDS blocks of the travel)."""
    r = _less_nuisance(f, nuisance)
    k, spectrum, usable, grid = _travel_spectrum(x, r, speed, ts, quantum, pace)
    usable &= k <= 2 * np.pi / (2 * MIN_BINS * max(quantum, speed * ts))
    if not usable.any():
        raise DataError(f"the log travels {np.ptp(x):.6g}: too short to find the cogging's period; "
                        "give --pitch")
    z, level = _peak_z(spectrum, usable)
    if z.max() <= level:
        return None
    j = int(np.argmax(z))
    peak = _refined_peak(x, r, float(k[j]), grid) / _subharmonic(k, spectrum, z, j, grid)
    # the harmonics of the period: a travel of a few periods places one sinusoid's peak only
    # roughly (its neighbours' leakage, a drift of the friction), the whole series sharply
    harmonics = max(1, min(PERIOD_HARMONICS, int(k[usable].max() / peak)))
    thin = slice(None, None, max(1, x.size // PERIOD_ROWS))
    xs, rs = x[thin], r[thin]
    k = _refined_peak(xs, rs, peak, grid, harmonics)
    blocks = np.array_split(np.arange(xs.size), FIT_FOLDS)
    ks = np.array([_refined_peak(np.delete(xs, b), np.delete(rs, b), k, grid, harmonics) for b in blocks])
    se = np.sqrt((FIT_FOLDS - 1) / FIT_FOLDS * np.sum((ks - ks.mean()) ** 2))
    return float(2 * np.pi / k), float(2 * np.pi / k ** 2 * se)


def _subharmonic(k: np.ndarray, spectrum: np.ndarray, z: np.ndarray, j: int, grid: float) -> int:
    """Which harmonic of the fundamental the strongest peak ``k[j]`` is: the largest n (up to
    PERIOD_HARMONICS) whose k[j] / n holds a local peak of the periodogram (within 2 FFT
    spacings) above the noise (``_peak_z``'s z; the level noise reaches with probability ALPHA
    over the n tried) and at least UNEXPLAINED_SHARE of the strongest (the friction's drifts
    along the travel and the strong peaks' side lobes stand above the noise too), else 1: the
    strongest harmonic need not be the first (a linear motor's 6th of its pole pitch had given
    a map of a sixth of the pitch, 37 % off)."""
    level = np.sqrt(2 * np.log((PERIOD_HARMONICS - 1) / ALPHA))
    for n in range(PERIOD_HARMONICS, 1, -1):
        near = np.flatnonzero(np.abs(k - k[j] / n) <= 2 * grid)
        if near.size == 0:
            continue
        i = int(near[np.argmax(spectrum[near])])
        local = 0 < i < k.size - 1 and spectrum[i] >= max(spectrum[i - 1], spectrum[i + 1])
        if local and z[i] > level and spectrum[i] >= UNEXPLAINED_SHARE * spectrum[j]:
            return n
    return 1


def _refined_peak(x, r, peak, grid, harmonics: int = 1) -> float:
    """The wavenumber within one FFT spacing of ``peak`` whose sinusoid (with its ``harmonics``
    - 1 overtones) leaves r the least residual sum of squares (bounded Brent)."""
    h = np.arange(1, harmonics + 1)

    def rss(wavenumber):
        phase = np.outer(x, wavenumber * h)
        return lstsq(np.hstack([np.sin(phase), np.cos(phase)]), r)[1]
    return refine(rss, peak - grid, peak + grid)


def _unexplained(x, r, period, highest, speed, ts, quantum, strongest, pace=None) -> Optional[float]:
    """The wavelength of a position-periodic force left in the residual r that no harmonic of
    ``period`` holds (a wrong period given): of the wavelengths from a UNEXPLAINED_PERIODS-th of
    the travel down to the shortest harmonic screened (``highest``), the periodogram's peak that
    stands highest above the running median around it, when noise alone reaches it with
    probability below ALPHA (Rayleigh) and its wavenumber (refined, ``_refined_peak``) is not
    within one FFT spacing of a multiple of 2 pi / period, and its amplitude is at least
    UNEXPLAINED_SHARE of ``strongest`` (the map's strongest harmonic's; 0 without a map); else
    None."""
    k, spectrum, usable, grid = _travel_spectrum(x, r, speed, ts, quantum, pace)
    usable &= (k <= 2 * np.pi * highest / period) & (k >= 2 * np.pi * UNEXPLAINED_PERIODS / np.ptp(x))
    if usable.sum() < 2:
        return None
    z, level = _peak_z(spectrum, usable)
    j = int(np.argmax(z))
    if z[j] <= level:
        return None
    peak = _refined_peak(x, r, k[j], grid)
    h = peak * period / (2 * np.pi)
    if abs(h - round(h)) * 2 * np.pi / period <= grid and round(h) >= 1:
        return None
    (sine, cosine), _ = lstsq(np.column_stack([np.sin(peak * x), np.cos(peak * x)]), r)
    return float(2 * np.pi / peak) if np.hypot(sine, cosine) >= UNEXPLAINED_SHARE * strongest else None


def identify_cogging(t, x, force, period: Optional[float] = None, inertia: Optional[float] = None,
                     fed_forward: Optional[CoggingMap] = None,
                     fed_forward_friction: Optional[CoggingMap] = None) -> CoggingFit:
    """The cogging map of a log (see the module docstring).

    Parameters
    ----------
    t, x, force : array_like
        Time (s, uniform), position (m or rad, e.g. encoder counts times their size) and the
        drive force (N or Nm: the current times the force constant).
    period : float, optional
        P, the fundamental period (a revolution: 2 pi rad; a pole pitch; a screw lead); if not
        given, the wavelength of the strongest position harmonic in the data (``_fundamental``:
        a travel of at least two of them).
    inertia : float, optional
        The moving mass or inertia; identified from the log if not given.
    fed_forward, fed_forward_friction : CoggingMap, optional
        The map of a first calibration that the drive fed forward in this move (a second
        calibration: the force holds the whole cogging again, now with little velocity ripple),
        and the friction's ripple found beside it: the map's candidates are the first map's
        harmonics, the ripple's the first ripple's (the feedforward, read at the counts, adds
        lines at the encoder's aliases less the map's harmonics); the period is the first
        map's; J is not told from a ripple this small (give ``inertia``).

    Returns
    -------
    CoggingFit
        ``DataError`` for a log that does not cover one period in each direction.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 16, 1e-3)
    >>> x = 2 * np.pi * 2 * (1 - np.abs(1 - t / 8))                 # two turns out, two back
    >>> v = np.gradient(x, t)
    >>> rng = np.random.default_rng(0)
    >>> f = 0.05 * np.sin(24 * x + 0.3) + 0.02 * np.sign(v) + 0.005 * rng.standard_normal(t.size)
    >>> fit = identify_cogging(t, x, f, period=2 * np.pi, inertia=0.0)
    >>> fit.map.harmonics, round(float(fit.map.amplitude[0]), 3), fit.friction
    ((24,), 0.05, None)
    """
    with blas_threads(wanted_threads()):
        return _identify(t, x, force, period, inertia, fed_forward, fed_forward_friction)


def _identify(t, x, force, period, inertia, fed_forward, fed_forward_friction) -> CoggingFit:
    t, x, f = (np.asarray(c, dtype=float) for c in (t, x, force))
    for name, values in (("t", t), ("x", x), ("force", f)):
        check_finite(name, values)
    try:
        _, ts = uniform_time(t)
    except DataError as exc:
        raise DataError(f"{exc}: a cogging map needs one log sampled without pauses (train the "
                        "longest part between gaps)") from None
    if fed_forward is not None:
        if period is not None and not np.isclose(period, fed_forward.period, rtol=1e-6, atol=0):
            raise DataError(f"the period {period:.9g} is not the fed-forward map's "
                            f"({fed_forward.period:.9g}): leave the period out")
        period = fed_forward.period
    if period is not None and not (np.isfinite(period) and period > 0):
        raise DataError(f"the cogging period must be a finite number > 0, got {period!r}")
    if period is not None and np.ptp(x) < period:
        raise DataError(f"the log travels {np.ptp(x):.6g}, less than one period ({period:.6g}); "
                        "a cogging map needs the whole period each way")
    window = _odd(INERTIA_WINDOW / ts)
    quantum = position_quantum(x)
    # the derivatives from the position between its count edges; the map keeps the counts the
    # drive reads
    moved = between_edges(t, x) if quantum > 0 else x
    v, a_smooth = smooth(moved, window, 1, ts), smooth(moved, window, 2, ts)
    rows = _moving(v, window)
    if rows.sum() < 10 * MIN_BINS:
        raise DataError("the log has too few rows in motion for a cogging map")
    steady_travel = _travel_share(moved, rows)
    sign = np.sign(v)
    speeds = tuple(float(s) for s in np.percentile(np.abs(v[rows]), (5, 50, 95)))
    speed = speeds[1]
    spread = 1.4826 * float(np.median(np.abs(np.abs(v[rows]) - speed))) / speed
    pace = None                     # a steady speed: from the position's steps where it holds
    if spread <= STEADY_SPREAD:
        steady = (rows & (np.abs(np.abs(v) - speed) <= 3 * max(spread, SPEED_PRECISION) * speed))[:-1]
        pace = float(np.mean(np.abs(np.diff(x))[steady])) / ts if steady.any() else None
    period_se = None
    if period is None:      # in the force less a given inertia's m a (a log of normal operation accelerates)
        less = f - inertia * a_smooth if inertia is not None else f
        found = _fundamental(x[rows], less[rows], _nuisance(v[rows]), speed, ts, quantum, pace)
        period, period_se = found if found is not None else (None, None)
        if period is None:                  # no position-periodic force: no map, the friction
            coef, rss = lstsq(_nuisance(v[rows]), less[rows])
            return CoggingFit(map=None, friction=None, inertia=float(inertia or 0.0),
                              inertia_source="given" if inertia is not None else "undetermined",
                              coulomb_viscous=tuple(float(c) for c in coef), highest_harmonic=0,
                              residual_rms=float(np.sqrt(rss / rows.sum())), rows=int(rows.sum()),
                              screened_by="the travel's periodogram: no peak above the noise",
                              steady_travel=steady_travel, speeds=speeds)
    # the viscous columns take the speed averaged over one period's travel: the velocity ripple
    # that the cogging itself causes would otherwise take part of it
    v_mean = uniform_filter1d(v, min(max(1, int(round(period / (speed * ts)))), v.size), mode="nearest")
    calm = np.ones(rows.size, dtype=bool)
    calm[rows] = _not_transient(_less_nuisance(f[rows], _nuisance(v_mean[rows])))
    rows &= minimum_filter1d(calm, window, mode="nearest")      # and the window around them
    xs, ss = x[rows], sign[rows]
    nuisance = _nuisance(v_mean[rows])
    r = _less_nuisance(f[rows], nuisance)
    terms, highest, screened_by, bins = _screen(xs, r, ss, period, speed, ts, quantum, pace)
    if fed_forward is not None:
        ripple = () if fed_forward_friction is None else fed_forward_friction.harmonics
        terms = [(h, signed) for h, signed in terms if h in (ripple if signed else fed_forward.harmonics)]

    # J a: the heavily smoothed acceleration for the choice (low noise), the lightly smoothed one
    # for the coefficients (smoothing would attenuate J a; the count edges keep the encoder's
    # steps out of it)
    fastest = max([h for h, _ in terms], default=1) * speed / period
    a = smooth(moved, min(window, _odd(1.0 / (A_WINDOW_WAVES * fastest * ts))), 2, ts)
    given = inertia is not None
    if not given and fed_forward is None:
        inertia = _inertia(xs, r, a[rows], ss, period, bins,
                           [h for h, signed in terms if not signed and h > 1])
    determined = inertia is not None
    inertia = inertia if determined else 0.0
    target = (f - inertia * a)[rows]

    k = 2 * np.pi / period
    full = np.hstack([nuisance, _waves(xs, k, terms, ss)])
    n_terms = nested_cross_validation(full, (f - inertia * a_smooth)[rows],
                                      [4 + 2 * n for n in range(len(terms) + 1)]) - 1
    terms = terms[:n_terms]
    if determined and not given and not any(not signed and h > 1 for h, signed in terms):
        determined, inertia, target = False, 0.0, f[rows]     # J told from harmonics not kept
    design = full[:, :4 + 2 * n_terms]
    coef, rss = lstsq(design, target)
    se = _jackknife_se(design, target)

    def series(signed):
        picked = [(j, h) for j, (h, s) in enumerate(terms) if s == signed]
        if not picked:
            return None
        picked.sort(key=lambda p: p[1])
        at = [4 + 2 * j for j, _ in picked]
        return CoggingMap(period=float(period), harmonics=tuple(h for _, h in picked),
                          sine=tuple(float(coef[i]) for i in at),
                          cosine=tuple(float(coef[i + 1]) for i in at),
                          sine_se=tuple(float(se[i]) for i in at),
                          cosine_se=tuple(float(se[i + 1]) for i in at))

    found = series(False)
    strongest = max(found.amplitude) if found is not None else 0.0
    left = _unexplained(xs, target - design @ coef, period, highest, speed, ts, quantum, strongest, pace)
    return CoggingFit(map=found, friction=series(True), inertia=float(inertia),
                      inertia_source="given" if given else ("identified" if determined else "undetermined"),
                      coulomb_viscous=tuple(float(c) for c in coef[:4]), highest_harmonic=highest,
                      residual_rms=float(np.sqrt(rss / target.size)), rows=int(rows.sum()),
                      period=float(period), period_se=period_se, unexplained_wavelength=left,
                      screened_by=screened_by, steady_travel=steady_travel, speeds=speeds,
                      count_alias=count_alias(period, quantum, pace, ts, highest))
