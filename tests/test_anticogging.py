"""Anticogging (fricgen.fit.cogging, fricgen.effects.CoggingMap, train --cogging, NAME_cogging): the map identified from two
turns each way of a servo axis simulated from the motor's own law (fricgen/sim/servo_axis.py),
none on an axis without cogging, model.json's cogging object, and the emitted float and q15
functions against the series and the integer twin over every encoder count."""
import json
import shutil
from dataclasses import replace

import numpy as np
import pytest

from conftest import assert_builds_strictly
from fricgen import codegen
from fricgen.cli import main
from fricgen.codegen.cbuild import build, build_module
from fricgen.codegen.cogging_table import CoggingTable, q15_twin, q31_twin
from fricgen.effects import CoggingMap
from fricgen.fit.cogging import _not_transient, identify_cogging
from fricgen.errors import ModelError
from fricgen.model import FrictionModel
from fricgen.sim.servo_axis import TWO_PI, calibration_move, random_axis

CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler")


def calibration(axis):
    """Two turns each way at 1.5 rad/s, logged at the drive's rate: (t, x, force)."""
    log = calibration_move(axis, turns=2.0, speed=1.5, every=1)
    return log["t"], log["x"], axis.kt * log["i"]


@pytest.fixture(scope="module")
def axis():
    return random_axis(17, bits=12)


@pytest.fixture(scope="module")
def fitted(axis):
    return identify_cogging(*calibration(axis), period=TWO_PI)


def test_map_from_two_turns_is_within_ten_percent(axis, fitted):
    assert axis.map_error(fitted.map) < 0.10
    assert axis.period_count in fitted.map.harmonics and 1 in fitted.map.harmonics


def test_each_harmonic_has_a_standard_error_smaller_than_itself(fitted):
    assert np.all(fitted.map.amplitude_se > 0)
    assert np.all(fitted.map.amplitude > 3 * fitted.map.amplitude_se)


def test_position_friction_is_kept_apart_from_the_position_force(axis, fitted):
    # the axis' friction varies once and twice per turn; its unbalance is once per turn
    assert fitted.friction is not None and {1, 2} & set(fitted.friction.harmonics)
    h1 = fitted.map.harmonics.index(1)
    assert fitted.map.amplitude[h1] == pytest.approx(axis.unbalance[0], rel=0.15)


def test_a_stall_at_one_position_keeps_the_harmonics_screened(axis, fitted):
    t, x, force = calibration(axis)
    below = np.mod(x, TWO_PI) - 1.0           # going back, each turn sticks for 0.01 rad at 1 rad
    stuck = (np.arange(x.size) > np.argmax(x)) & (below < 0) & (below > -0.01)
    x = np.where(stuck, x - below, x)
    stalled = identify_cogging(t, x, force, period=TWO_PI)
    assert stalled.highest_harmonic == fitted.highest_harmonic
    assert axis.map_error(stalled.map) < 0.10


def test_what_limits_the_harmonics_screened_is_named(axis, fitted):
    assert fitted.screened_by == "the encoder: 4096 counts per period"
    log = calibration_move(axis, turns=2.0, speed=8.0, every=4)      # fast, logged at 2 kHz
    fast = identify_cogging(log["t"], log["x"], axis.kt * log["i"], period=TWO_PI)
    assert fast.highest_harmonic < fitted.highest_harmonic
    assert fast.screened_by.startswith("the sample rate: ") and "samples per period at this speed" in fast.screened_by


def test_the_encoders_count_aliased_by_a_2_khz_log_is_no_wrong_period(axis):
    """Logged at 2 kHz, a 12-bit calibration at 1 rad/s holds weak lines of the count's harmonics
    aliased by the sample rate; they were warned of as 'a wrong --pitch?' on every such log."""
    log = calibration_move(axis, turns=2.0, speed=1.0, every=4)
    fit = identify_cogging(log["t"], log["x"], axis.kt * log["i"], period=TWO_PI)
    assert axis.map_error(fit.map) < 0.10 and fit.unexplained_wavelength is None
    assert identify_cogging(log["t"], log["x"], axis.kt * log["i"], period=1.0).unexplained_wavelength


def test_a_count_rate_the_log_folds_into_the_band_is_warned_of_and_its_sidebands_left_out(tmp_path, capsys):
    """At 3 rad/s a 12-bit encoder counts at 1956 Hz, which a 2 kHz log folds to harmonic 93 of
    the turn; the cogging's speed ripple modulates the drive's ripple there, and the lines at 93
    -+ the cogging's harmonics had made the map 50 % off (the speed's spread, 9 %, had also
    kept the alias from being placed at all). Train says so; at 1 rad/s it does not."""
    axis = random_axis(3)
    for speed, warned in ((3.0, True), (1.0, False)):
        log = calibration_move(axis, turns=2.0, speed=speed, every=4)
        fit = identify_cogging(log["t"], log["x"], axis.kt * log["i"], period=TWO_PI)
        assert axis.map_error(fit.map) < 0.10
        assert (fit.count_alias is not None) == warned
        path = tmp_path / f"cal{speed:g}.csv"
        np.savetxt(path, np.column_stack([log["t"], log["x"], log["i"]]), delimiter=",",
                   header="t,x,i", comments="", fmt="%.9g")
        assert main(["train", str(path), "--cogging", "--rotary", "--force-constant", str(axis.kt),
                     "-o", str(tmp_path / f"m{speed:g}.json")]) == 0
        said = "the encoder's count rate at this speed is above half the log's rate" in capsys.readouterr().err
        assert said == warned


def test_an_axis_without_cogging_gets_no_map():
    axis = replace(random_axis(23, bits=14), cogging=(), unbalance=(0.0, 0.0), ripple=(0.0, 0.0),
                   position_friction=())
    fit = identify_cogging(*calibration(axis), period=TWO_PI)
    assert fit.map is None


def test_a_move_shorter_than_one_period_is_refused(axis):
    t, x, f = calibration(axis)
    with pytest.raises(Exception, match="less than one period"):
        identify_cogging(t, x, f, period=100.0)


# ----------------------------------------------------------------------------- model.json

@pytest.fixture(scope="module")
def model(fitted):
    from fricgen.fit.textbook import fit_law
    law = fit_law(np.array([0.5, 1.0, 2.0]), np.array([0.02, 0.021, 0.022]))
    base = FrictionModel.from_directions(law.direction(), name="axis_c", training={"units": "rotary"})
    return replace(base, cogging_map=fitted.map, cogging_friction=fitted.friction)


def test_model_json_round_trip_keeps_the_map_and_its_hash(model, tmp_path):
    path = model.save(tmp_path / "m.json")
    back = FrictionModel.load(path)
    assert back.cogging_map == model.cogging_map and back.model_hash == model.model_hash
    x = np.linspace(-7, 7, 11)
    np.testing.assert_allclose(back.cogging(x), model.cogging_map.force(x))
    assert replace(model, cogging_map=None).model_hash != model.model_hash


def test_a_model_without_a_map_has_zero_cogging(model):
    assert replace(model, cogging_map=None).cogging(np.ones((2, 3))).tolist() == [[0.0] * 3] * 2


@pytest.mark.parametrize("edit, message", [
    (lambda c: c["map"].update(harmonics=[1, 1]), "distinct"),
    (lambda c: c["map"].update(sine=[0.1]), "sine must list"),
    (lambda c: c["map"].update(period=-1), "period"),
    (lambda c: c.update(other={}), "cogging must be"),
    (lambda c: c["map"].update(period=4 * np.pi), r"cogging.map.period 12.5664 rad is longer than a turn"),
])
def test_a_hand_edited_cogging_object_is_refused(model, edit, message):
    d = json.loads(model.to_json())
    edit(d["cogging"])
    with pytest.raises(ModelError, match=message):
        FrictionModel.from_dict(d)


# ----------------------------------------------------------------------------- C

CDEF = """float axis_c_cogging(float x); int16_t axis_c_cogging_q15(uint32_t phase);
int32_t axis_c_cogging_q31(uint32_t phase);"""


@pytest.fixture(scope="module")
def lib(model, tmp_path_factory):
    folder = tmp_path_factory.mktemp("cogging_c")
    for fname, text in codegen.render(model).items():
        (folder / fname).write_text(text)
    return folder, build(folder, "axis_c.h", CDEF)


@needs_cc
def test_float_cogging_is_within_its_stated_bound(model, lib):
    folder, c = lib
    table = CoggingTable.of(model.cogging_map)
    x = np.concatenate([np.linspace(-20.0, 20.0, 20001), np.arange(64) * TWO_PI / 64])
    x = x.astype(np.float32).astype(float)                 # the position the C is given
    got = np.array([c.axis_c_cogging(float(v)) for v in x])
    bound = float((folder / "axis_c.h").read_text().split("AXIS_C_COGGING_ERROR_BOUND ")[1].split("f")[0])
    assert bound == pytest.approx(table.float_bound, rel=1e-6)
    assert np.max(np.abs(got - model.cogging(x))) <= bound


@needs_cc
def test_float_cogging_far_from_zero_stays_within_its_bound(model, lib):
    table = CoggingTable.of(model.cogging_map)
    turns = np.array([-4000, -1000, -7, 3, 100, 1000, 4000])
    x = (np.linspace(0.0, TWO_PI, 97)[None, :] + TWO_PI * turns[:, None]).astype(np.float32).ravel()
    got = np.array([lib[1].axis_c_cogging(float(v)) for v in x])
    assert np.max(np.abs(got - model.cogging(x.astype(float)))) <= table.float_bound


@needs_cc
def test_the_float_bound_holds_the_phase_rounding_of_high_harmonics(model, tmp_path):
    """Harmonics 288 and 576 of a turn (a 36-slot, 32-pole motor): at every 14-bit count of a
    turn, and shifted by whole turns, within the bound against the map at the float x given
    (the bound holds the phase's float rounding, the map's slope times a period's eps; x's own
    rounding, as x + 3 turns summed in float, is the caller's: the header says so)."""
    cogging = CoggingMap(period=TWO_PI, harmonics=(288, 576), sine=(0.03, 0.012),
                         cosine=(-0.025, 0.006), sine_se=(0.0, 0.0), cosine_se=(0.0, 0.0))
    steep = replace(model, cogging_map=cogging, cogging_friction=None)
    for fname, text in codegen.render(steep).items():
        (tmp_path / fname).write_text(text)
    c = build(tmp_path, "axis_c.h", CDEF)
    bound = CoggingTable.of(cogging).float_bound
    counts = np.arange(1 << 14) * TWO_PI / (1 << 14)
    for shift in (0.0, 3.0, -5.0, 100.0):
        x = (counts + shift * TWO_PI).astype(np.float32).astype(float)
        got = np.array([c.axis_c_cogging(float(v)) for v in x])
        assert np.max(np.abs(got - cogging.force(x))) <= bound


@needs_cc
@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf"), 1e30])
def test_float_cogging_gives_zero_for_an_unusable_position(lib, value):
    assert lib[1].axis_c_cogging(value) == 0.0


@needs_cc
@pytest.mark.parametrize("bits", [12, 14])
@pytest.mark.parametrize("q", [15, 31])
def test_the_fixed_point_map_matches_its_twin_and_its_bound_at_every_count(model, lib, bits, q):
    """q15 and q31 at every count of the encoder (q31 also between counts: its fraction's low
    bits), bit for bit their numpy twins, within their stated bounds."""
    table = CoggingTable.of(model.cogging_map)
    function, twin, values, dtype = {15: ("axis_c_cogging_q15", q15_twin, table.q15, np.int16),
                                     31: ("axis_c_cogging_q31", q31_twin, table.q31, np.int32)}[q]
    counts = np.arange(2 ** bits, dtype=np.uint64)
    phase = (counts << np.uint64(32 - bits)).astype(np.uint32)
    if q == 31:
        phase[1::2] += np.uint32(12345)
    got = np.array([getattr(lib[1], function)(int(p)) for p in phase], dtype=dtype)
    np.testing.assert_array_equal(got, twin(values, phase))
    scale, bound = (table.q15_scale, table.q15_bound) if q == 15 else (table.q31_scale, table.q31_bound)
    force = got * (scale / 2.0 ** q)
    exact = model.cogging(phase.astype(float) * TWO_PI / 2.0 ** 32)
    assert np.max(np.abs(force - exact)) <= bound
    # q31 keeps what q15 rounds away: its bound is the interpolation's, q15's adds its LSB
    assert table.q31_bound < table.q15_bound


def test_q31_twin_at_the_extreme_phases_stays_in_range_and_hits_the_table(model):
    table = CoggingTable.of(model.cogging_map)
    phase = np.array([0, 1, 2 ** 31, 2 ** 32 - 1], dtype=np.uint32)
    out = q31_twin(table.q31, phase)
    assert np.all(np.abs(out.astype(np.int64)) <= 2 ** 31 - 1)
    knots = (np.arange(table.points, dtype=np.uint64) << np.uint64(32 - table.points.bit_length() + 1))
    np.testing.assert_array_equal(q31_twin(table.q31, knots.astype(np.uint32)), table.q31)


def test_q15_twin_at_the_extreme_phases_stays_in_range(model):
    table = CoggingTable.of(model.cogging_map)
    phase = np.array([0, 1, 2 ** 31, 2 ** 32 - 1], dtype=np.uint32)
    out = q15_twin(table.q15, phase)
    assert np.all(np.abs(out.astype(int)) <= 32767)


@needs_cc
def test_emitted_cogging_builds_strictly(lib):
    assert_builds_strictly(lib[0], "axis_c.c", CC)


@pytest.fixture(scope="module")
def maplib(model, tmp_path_factory):
    """The emitted model with its RAM map's API (the cffi declarations of NAME.h's)."""
    folder = tmp_path_factory.mktemp("cogging_map_c")
    for fname, text in codegen.render(model).items():
        (folder / fname).write_text(text)
    points = CoggingTable.of(model.cogging_map).points
    cdef = CDEF + f"""
typedef struct {{ float table[{points}]; }} axis_c_cogging_map_t;
void axis_c_cogging_map_init(axis_c_cogging_map_t *map);
float axis_c_cogging_map_at(const axis_c_cogging_map_t *map, float x);
uint32_t axis_c_cogging_map_save(const axis_c_cogging_map_t *map, const char *model_hash,
                                 unsigned char *buf, uint32_t size);
int32_t axis_c_cogging_map_restore(axis_c_cogging_map_t *map, const char *model_hash,
                                   const unsigned char *buf, uint32_t size);"""
    return build_module(folder, "axis_c.h", cdef, build_dir=folder / "build")


def _restore(maplib, blob, model_hash):
    ffi, c = maplib.ffi, maplib.lib
    m = ffi.new("axis_c_cogging_map_t *")
    code = c.axis_c_cogging_map_restore(m, ffi.NULL if model_hash is None else model_hash.encode(),
                                        blob, len(blob))
    return code, m


def _with_crc(body):
    import struct
    import zlib
    return body + struct.pack("<I", zlib.crc32(body))


@needs_cc
def test_the_map_saved_by_c_is_the_blob_python_writes_and_restores_to_the_same_forces(model, maplib):
    ffi, c = maplib.ffi, maplib.lib
    table = CoggingTable.of(model.cogging_map)
    m = ffi.new("axis_c_cogging_map_t *")
    c.axis_c_cogging_map_init(m)
    buf = ffi.new("unsigned char[]", 32 + 4 * table.points)
    assert c.axis_c_cogging_map_save(m, model.model_hash.encode(), buf, len(buf)) == len(buf)
    assert c.axis_c_cogging_map_save(m, model.model_hash.encode(), buf, len(buf) - 1) == 0
    blob = table.blob(model.model_hash)
    assert bytes(ffi.buffer(buf)) == blob
    code, back = _restore(maplib, blob, model.model_hash)
    assert code == 0
    x = np.linspace(-20.0, 20.0, 4001)
    assert [c.axis_c_cogging_map_at(back, float(u)) for u in x] == [c.axis_c_cogging(float(u)) for u in x]
    assert c.axis_c_cogging_map_at(ffi.NULL, 1.0) == 0.0


@needs_cc
def test_one_units_map_restores_without_a_hash_and_a_bad_blob_is_refused_untouched(model, maplib):
    """Another unit's map (its own model, the same table size and period) restores where no
    hash is asked for, and is then what the firmware computes; a blob of the wrong size, another
    period, a hash that is not the one asked for, a flipped bit or a NaN is refused and the map
    keeps what it held."""
    ffi, c = maplib.ffi, maplib.lib
    unit = replace(model, cogging_map=replace(model.cogging_map, sine=tuple(0.8 * np.asarray(model.cogging_map.sine)),
                                              cosine=tuple(1.3 * np.asarray(model.cogging_map.cosine))))
    table = CoggingTable.of(unit.cogging_map)
    assert table.points == CoggingTable.of(model.cogging_map).points
    blob = table.blob(unit.model_hash)
    code, m = _restore(maplib, blob, None)
    assert code == 0
    x = np.linspace(-7.0, 7.0, 501).astype(np.float32).astype(float)
    got = np.array([c.axis_c_cogging_map_at(m, float(u)) for u in x])
    assert np.max(np.abs(got - unit.cogging(x))) <= table.float_bound
    assert _restore(maplib, blob, model.model_hash)[0] == -4          # not the model asked for
    body = bytearray(blob[:-4])
    body[8:12] = np.float32(1.0).tobytes()                            # another period
    bad = {"size": (blob[:-1], -3), "period": (_with_crc(bytes(body)), -4),
           "bit": (blob[:40] + bytes([blob[40] ^ 1]) + blob[41:], -5),
           "nan": (_with_crc(blob[:28] + np.float32("nan").tobytes() + blob[32:-4]), -6)}
    for what, (data, expected) in bad.items():
        before = [m.table[k] for k in range(table.points)]
        assert c.axis_c_cogging_map_restore(m, ffi.NULL, data, len(data)) == expected, what
        assert [m.table[k] for k in range(table.points)] == before, what


def test_emit_writes_the_map_blob_or_refuses_in_one_line(model, tmp_path, capsys):
    path = model.save(tmp_path / "m.json")
    blob = tmp_path / "unit.bin"
    assert main(["emit", str(path), "-o", str(tmp_path / "c"), "--cogging-blob", str(blob)]) == 0
    assert blob.read_bytes() == CoggingTable.of(model.cogging_map).blob(model.model_hash)
    plain = replace(model, cogging_map=None).save(tmp_path / "plain.json")
    out = tmp_path / "c2"
    capsys.readouterr()
    assert main(["emit", str(plain), "-o", str(out), "--cogging-blob", str(tmp_path / "u2.bin")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds no cogging map" in err[0]
    assert not out.exists() and not (tmp_path / "u2.bin").exists()


def test_fixed_point_emit_refuses_a_model_with_a_map(model):
    with pytest.raises(ModelError, match="cogging map"):
        codegen.render(model, dtype="q15")


# ----------------------------------------------------------------------------- command line

@pytest.fixture(scope="module")
def calibration_csv(axis, tmp_path_factory):
    t, x, f = calibration(axis)
    path = tmp_path_factory.mktemp("cal") / "cal.csv"
    np.savetxt(path, np.column_stack([t, x, f / axis.kt]), delimiter=",", header="t,x,i",
               comments="", fmt="%.9g")
    return path


def test_symmetric_holds_with_cogging(calibration_csv, axis, tmp_path, capsys):
    """--symmetric with --cogging: one friction curve (it was ignored: the model stayed per
    direction and emit --dtype q15 then refused it as asymmetric), the map the same."""
    out = {}
    for flag in ("--symmetric", "--asymmetric"):
        out[flag] = tmp_path / f"m{flag}.json"
        assert main(["train", str(calibration_csv), "--cogging", "--rotary", "--force-constant",
                     str(axis.kt), flag, "-o", str(out[flag])]) == 0
    capsys.readouterr()
    one, two = (FrictionModel.load(out[f]) for f in ("--symmetric", "--asymmetric"))
    assert one.symmetric and not two.symmetric
    assert one.cogging_map == two.cogging_map
    speed = 0.5
    assert one.force(speed) == pytest.approx((two.force(speed) - two.force(-speed)) / 2, rel=0.05)


def test_an_inertia_the_calibration_cannot_show_is_not_emitted(tmp_path, capsys):
    """A calibration whose two directions' ripple does not determine J (the map takes out none
    and holds J a): the friction fit of the same log must not report an inertia either (from
    the ripple the map holds it found one, which the header emitted as identified)."""
    axis = random_axis(21, bits=14)
    log = calibration_move(axis, turns=2.0, speed=1.0, every=4)
    path = tmp_path / "cal.csv"
    np.savetxt(path, np.column_stack([log["t"], log["x"], log["omega"], log["i"]]), delimiter=",",
               header="t,x,v,i", comments="", fmt="%.9g")
    out = tmp_path / "m.json"
    assert main(["train", str(path), "--cogging", "--rotary", "--force-constant", str(axis.kt),
                 "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "taken as 0: the map holds the inertia's ripple" in text
    assert "inertia   not determined: the calibration accelerates only by the ripple" in text
    assert FrictionModel.load(out).axis.mass is None
    codegen.emit(FrictionModel.load(out), tmp_path / "c", "cal")
    assert "INERTIA" not in (tmp_path / "c" / "cal.h").read_text()


@pytest.mark.parametrize("seed", [1001, 1002])
def test_a_calibration_at_one_speed_gives_its_level_at_every_speed(tmp_path, capsys, seed):
    """A calibration at 1 rad/s each way: its velocity ripple spreads the speeds over 0.75-1.27
    rad/s, and the default fit drew a viscous line through 0 over them (a quarter of the
    friction at 0.3 rad/s, six times it at 6 rad/s). The model is the level the move measured."""
    axis = random_axis(seed)
    log = calibration_move(axis, turns=2.0, speed=1.0, every=4)
    path = tmp_path / "cal.csv"
    np.savetxt(path, np.column_stack([log["t"], log["x"], log["i"]]), delimiter=",",
               header="t,x,i", comments="", fmt="%.9g")
    out = tmp_path / "m.json"
    assert main(["train", str(path), "--cogging", "--rotary", "--force-constant", str(axis.kt),
                 "-o", str(out)]) == 0
    assert "the move holds one speed" in capsys.readouterr().out
    model = FrictionModel.load(out)
    speeds = np.array([0.3, 1.0, 3.0, 6.0])
    truth = (axis.coulomb + (axis.static - axis.coulomb) * np.exp(-(speeds / axis.stribeck) ** 2)
             + axis.viscous * speeds)
    assert model.training["method"] == "level_at_one_speed"
    assert np.all(np.abs(model.force(speeds) / truth - 1) < 0.25)
    assert np.all(np.abs(model.force(-speeds) / truth + 1) < 0.25)


def test_train_cogging_writes_the_map_and_eval_adds_it(calibration_csv, axis, tmp_path, capsys):
    out = tmp_path / "m.json"
    assert main(["train", str(calibration_csv), "--cogging", "--rotary", "--force-constant",
                 str(axis.kt), "-o", str(out)]) == 0
    captured = capsys.readouterr()
    text = captured.out
    assert "cogging map (position force)" in text and f"harmonic {axis.period_count:4d}" in text
    assert "harmonics screened up to 512 (set by the encoder: 4096 counts per period)" in text
    assert "a wrong --pitch" not in captured.err
    model = FrictionModel.load(out)
    # the friction is fitted with the inertia the map identified (a move at one speed
    # accelerates too little to tell it again: a new user's 17-bit calibration read 5x low)
    assert "(identified from the two directions' ripple)" in text
    assert model.axis.mass_from == "cogging" and model.axis.mass == pytest.approx(axis.inertia, rel=0.3)
    assert axis.map_error(model.cogging_map) < 0.10
    assert "compensates nothing" not in captured.err and "fricgen: fricgen:" not in captured.err


def test_the_friction_of_a_calibration_takes_the_inertia_the_map_identified(tmp_path, capsys):
    """A new user's 17-bit calibration logged at 2 kHz: the friction's own inverse dynamics read
    the inertia 5x low (a move at one speed accelerates only at its ends), beside the map's right
    one, and the header kept the wrong one."""
    axis = random_axis(17, bits=14)
    log = calibration_move(axis, turns=2.0, speed=1.5, every=4)
    path = tmp_path / "cal.csv"
    np.savetxt(path, np.column_stack([log["t"], log["x"], log["i"]]), delimiter=",", header="t,x,i",
               comments="", fmt="%.9g")
    assert main(["train", str(path), "--cogging", "--rotary", "--force-constant", str(axis.kt),
                 "-o", str(tmp_path / "m.json")]) == 0
    lines = capsys.readouterr().out.splitlines()
    model = FrictionModel.load(tmp_path / "m.json")
    assert model.axis.mass_from == "cogging" and model.axis.mass == pytest.approx(axis.inertia, rel=0.3)
    assert any(line.startswith("inertia") and "from the cogging map's ripple (below)" in line for line in lines)
    assert not any(line.startswith("friction: Coulomb + viscous per direction from the move") for line in lines)


def test_a_calibration_logged_too_coarsely_for_its_speed_says_the_compensation_is_zero(
        axis, tmp_path, capsys):
    """Logged at 2 kHz, a 12-bit encoder resolves 3 rad/s a count: NAME_compensation's zero
    band covers the whole 1.5 rad/s calibration, and one warning says that it compensates
    nothing at the speeds trained (a new user's trial)."""
    t, x, f = calibration(axis)
    path = tmp_path / "cal.csv"
    np.savetxt(path, np.column_stack([t, x, f / axis.kt])[::4], delimiter=",", header="t,x,i",
               comments="", fmt="%.9g")
    assert main(["train", str(path), "--cogging", "--rotary", "--force-constant", str(axis.kt),
                 "-o", str(tmp_path / "m.json")]) == 0
    model = FrictionModel.load(tmp_path / "m.json")
    assert model.velocity_band >= model.training["axis"]["speed_max"]
    err = capsys.readouterr().err
    assert err.count("compensates nothing at the speeds trained") == 1 and "fricgen: fricgen:" not in err
    assert model.axis.force_constant == pytest.approx(axis.kt)     # the friction saw a force


@pytest.mark.parametrize("argv, message", [
    (["--pitch", "0.01"], "--pitch is for --cogging's map"),
    (["--cogging", "--rotary"], "needs --force-constant"),
    (["--cogging", "--force-constant", "0.08", "--rotary", "--pitch", "100"], "longer than a turn"),
    (["--cogging", "--force-constant", "0.08", "--rotary", "--pitch", "7.8"], "longer than a turn"),
])
def test_train_cogging_refuses_what_it_cannot_do(calibration_csv, tmp_path, capsys, argv, message):
    out = tmp_path / "m.json"
    assert main(["train", str(calibration_csv), "-o", str(out), *argv]) != 0
    assert message in capsys.readouterr().err and not out.exists()


def test_a_wrong_pitch_is_refused_not_written(calibration_csv, axis, tmp_path, capsys):
    """A --pitch whose harmonics miss a force the log holds gave a map that misses it, with a
    warning beside the written model; it is now refused, in one line."""
    out = tmp_path / "m.json"
    assert main(["train", str(calibration_csv), "--cogging", "--rotary", "--pitch", "1.0",
                 "--force-constant", str(axis.kt), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "that no harmonic of the period 1 holds: check --pitch" in err
    assert err.count("\n") == 1 and "Is x in deg?" not in err and not out.exists()


def _pole_pitches(pitches, seed=0):
    """A linear motor cogging every pole pitch (32 mm: harmonics 1, 2, 6, 12, the 1st the
    strongest of the odd ones), ``pitches`` of travel each way at 10 mm/s, 4 kHz, 1 um counts:
    the path of its CSV (t, x, force)."""
    rng = np.random.default_rng(seed)
    pitch, speed, rate = 0.032, 0.01, 4000.0
    turn = pitches * pitch / speed
    t = np.arange(0, 2 * turn, 1 / rate)
    x = np.round(speed * (turn - np.abs(t - turn)) / 1e-6) * 1e-6
    h, amp = np.array([1, 2, 6, 12]), np.array([1.0, 0.4, 1.5, 0.6])
    cogging = (amp[:, None] * np.sin(np.outer(h, TWO_PI * x / pitch) + rng.uniform(0, 6, (4, 1)))).sum(0)
    v = np.gradient(x, t)
    return np.column_stack([t, x, cogging + 20 * np.sign(v) + 300 * v + 0.3 * rng.standard_normal(t.size)])


def test_a_pitch_in_mm_is_named(tmp_path, capsys):
    path, out = tmp_path / "lin.csv", tmp_path / "m.json"
    np.savetxt(path, _pole_pitches(2), delimiter=",", header="t,x,force", comments="", fmt="%.10g")
    assert main(["train", str(path), "--cogging", "--pitch", "32", "-o", str(out)]) == 2
    assert "(--pitch is in m: 0.032 for 32 mm)" in capsys.readouterr().err and not out.exists()


@pytest.mark.parametrize("pitches, pitch, refused", [(2, "0.016", True), (4, "0.032", False)])
def test_half_the_pole_pitch_is_refused_the_pitch_itself_not(tmp_path, capsys, pitches, pitch, refused):
    """--pitch half the pole pitch: its even harmonics hold all but the pitch's odd ones, and
    the map (56 % off on a new user's motor) was written without a word. The map of twice the
    pitch holds them; the pole pitch itself, over a travel that shows twice as long a period
    twice, passes that check."""
    path, out = tmp_path / "lin.csv", tmp_path / "m.json"
    np.savetxt(path, _pole_pitches(pitches), delimiter=",", header="t,x,force", comments="", fmt="%.10g")
    code = main(["train", str(path), "--cogging", "--pitch", pitch, "-o", str(out)])
    err = capsys.readouterr().err
    assert (code, out.exists()) == ((2, False) if refused else (0, True))
    assert ("repeats every 0.032 m, 2 times --pitch 0.016: its harmonic 1 (" in err) == refused


def test_a_calibration_too_fast_for_its_log_rate_is_warned_of(axis, tmp_path, capsys):
    log = calibration_move(axis, turns=2.0, speed=8.0, every=4)      # fast, logged at 2 kHz
    path = tmp_path / "fast.csv"
    np.savetxt(path, np.column_stack([log["t"], log["x"], log["i"]]), delimiter=",", header="t,x,i",
               comments="", fmt="%.9g")
    main(["train", str(path), "--cogging", "--rotary", "--force-constant", str(axis.kt),
          "-o", str(tmp_path / "m.json")])
    lines = [line for line in capsys.readouterr().err.splitlines() if "fast for the log's rate" in line]
    assert len(lines) == 1 and "a slower move or a faster log screens more" in lines[0]


def test_a_pitch_below_a_turn_names_the_harmonics_of_the_turn_it_drops(calibration_csv, axis, tmp_path, capsys):
    pitch = f"{TWO_PI / axis.pole_pairs:.6g}"
    assert main(["train", str(calibration_csv), "--cogging", "--rotary", "--pitch", pitch,
                 "--force-constant", str(axis.kt), "-o", str(tmp_path / "m.json")]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "leave --pitch out" in line]
    assert len(lines) == 1 and "holds harmonic 1 of the turn" in lines[0]
    assert f"(a turn is {axis.pole_pairs} of it)" in lines[0]
    assert FrictionModel.load(tmp_path / "m.json").cogging_map.period == pytest.approx(float(pitch))


def test_a_calibration_logged_in_degrees_is_named(axis, tmp_path, capsys):
    """A rotary log of x in degrees found no map, among other warnings a generic 'wrong --pitch,
    ... (degrees?)'; its force repeats every 360 / L units, which says degrees outright. It
    then wrote a model without a map, its friction at 57 times the speeds, beside a warning; it
    is refused in one line, as a map of the wrong period is."""
    t, x, f = calibration(axis)
    path, out = tmp_path / "deg.csv", tmp_path / "m.json"
    np.savetxt(path, np.column_stack([t, np.degrees(x), f / axis.kt])[::2], delimiter=",",
               header="t,x,i", comments="", fmt="%.9g")
    assert main(["train", str(path), "--cogging", "--rotary", "--force-constant", str(axis.kt),
                 "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Is x in deg?" in err and not out.exists()
    assert f"harmonic {axis.period_count} of the period 6.28319" in err and "--scale x=0.0174533" in err


def test_a_linear_motor_without_its_pitch_gets_the_period_from_the_data(tmp_path, capsys):
    axis = random_axis(29, bits=12, linear=True)
    t, x, f = calibration(axis)
    path = tmp_path / "lin.csv"
    np.savetxt(path, np.column_stack([t, x, f]), delimiter=",", header="t,x,force", comments="",
               fmt="%.10g")
    out = tmp_path / "m.json"
    assert main(["train", str(path), "--cogging", "-o", str(out)]) == 0
    assert "found from the data" in capsys.readouterr().out
    model = FrictionModel.load(out)
    assert model.cogging_map.period == pytest.approx(axis.pitch / axis.period_count, rel=1e-3)
    assert axis.map_error(model.cogging_map) < 0.10


def test_a_grey_box_without_an_admissible_fit_leaves_the_textbook_law(monkeypatch):
    """The default fit's grey-box may find no admissible curve (ValueError, as a new user's
    linear-motor log did): the textbook law is fitted instead of a traceback."""
    import fricgen
    from fricgen.fit.stribeck import StribeckRegressor

    def no_fit(self, x, t):
        raise ValueError("no fit of [F1] keeps sum |a_k| <= 10")
    monkeypatch.setattr(StribeckRegressor, "fit", no_fit)
    v = np.linspace(0.005, 0.2, 40)
    f = 20 + 10 * np.exp(-(v / 0.03) ** 2) + 30 * v
    report = fricgen.train({"v": np.concatenate([v, -v]), "f": np.concatenate([f, -f])})
    assert report.model.force(0.1) == pytest.approx(23.0, abs=0.3)
    assert "no fit of [F1]" in report.text


def test_diagnose_refuses_a_model_with_a_map_and_simulate_says_it_leaves_it_out(model, tmp_path, capsys):
    path = model.save(tmp_path / "m.json")
    log = tmp_path / "log.csv"
    log.write_text("t,x,i\n0,0,0\n")
    out = tmp_path / "diag"
    assert main(["diagnose", str(log), "--model", str(path), "-o", str(out)]) != 0
    assert "holds a cogging map" in capsys.readouterr().err and not out.exists()
    assert main(["simulate", "--model", str(path), "--duration", "0.05"]) == 0
    assert "leaves out" in capsys.readouterr().err


def _stepped_calibration(rate=8000.0, speed=1.0, bits=14):
    """Two turns each way at ``speed``, started and stopped by velocity steps: a decaying 30 Hz
    swing of 1 Nm for 60 ms after each (a soft loop's response), beside a cogging of 0.01 Nm at
    72, 144 and 216 per turn. (t, x in floored counts, force, the cogging as a function.)"""
    two_pi, q = 2 * np.pi, 2 * np.pi / 2 ** bits
    move = 2 * two_pi / speed
    t = np.arange(0.0, 2 * move + 1.0, 1 / rate)
    theta = np.where(t < 0.25, 0.0, np.where(t < 0.25 + move, speed * (t - 0.25), np.where(
        t < 0.75 + move, 2 * two_pi, np.maximum(2 * two_pi - speed * (t - 0.75 - move), 0.0))))

    def cogging(th):
        return 0.01 * np.sin(72 * th + 0.3) + 0.004 * np.sin(144 * th + 1.0) + 0.002 * np.sin(216 * th + 2.0)
    v = np.gradient(theta, t)
    f = cogging(theta) + 0.01 * np.sign(v) + 1e-3 * v + 5e-4 * np.random.default_rng(0).standard_normal(t.size)
    for start, sign in ((0.25, 1), (0.25 + move, -1), (0.75 + move, -1), (0.75 + 2 * move, 1)):
        m = (t >= start) & (t < start + 0.06)
        f[m] += sign * np.exp(-(t[m] - start) / 0.01) * np.cos(2 * np.pi * 30 * (t[m] - start))
    return t, np.floor(theta / q) * q, f, cogging


def test_a_calibration_started_by_velocity_steps_keeps_its_harmonics():
    """The few rows of each step's swing, 100x the cogging, spread over every harmonic's bin
    average: the map kept only the 72nd (41 % off) before they were left out."""
    t, x, f, cogging = _stepped_calibration()
    fit = identify_cogging(t, x, f, 2 * np.pi, inertia=0.0)
    q = 2 * np.pi / 2 ** 14
    counts = np.arange(2 ** 14) * q
    truth = cogging(counts + q / 2)                 # the floored count's mean position
    assert fit.map.harmonics == (72, 144, 216)
    assert np.sqrt(np.mean((fit.map.force(counts) - truth) ** 2)) < 0.05 * np.std(truth)


def test_a_smooth_force_has_no_transient_rows():
    force = np.sin(np.linspace(0.0, 20.0, 5000)) + 0.01 * np.random.default_rng(1).standard_normal(5000)
    assert _not_transient(force).all()
    force[100:110] += 50.0
    assert np.flatnonzero(~_not_transient(force)).tolist() == list(range(100, 110))
