"""model.json's axis record (training.axis) and the commands that use it: simulate runs the
model's axis, diagnose takes its mass and force constant, emit --dtype q15|q31 covers its speeds."""
import dataclasses
import json

import numpy as np
import pytest

from fricgen.axis import Axis
from fricgen.effects import ConstantLoad, with_effects
from fricgen.cli import main
from fricgen.cli.simulate import choose_plant
from fricgen.codegen import cbuild, fixedpoint as fx
from fricgen.control.loop import DEFAULT_SPEEDS
from fricgen.sim.trajectory import reversing, sampled
from fricgen.data.motionlog import log_csv_text
from fricgen.model import FrictionModel, ModelError
from fricgen.sim.logsynth import LogSpec, nominal_model, synthesize_log

RECORD = {"mass": 95.1, "mass_se": 0.12, "mass_from": "data", "force_constant": 1.0,
          "offset": -3.16, "offset_se": 0.05, "speed_min": 0.001, "speed_max": 0.128}
SWEEP = {"mass": None, "mass_se": None, "mass_from": None, "force_constant": None,
         "offset": None, "offset_se": None, "speed_min": 0.001, "speed_max": 0.2}


def with_axis(model, record):
    return dataclasses.replace(model, training={**model.training, "axis": record})


def test_the_record_round_trips_and_leaves_the_model_hash_alone(model10, tmp_path):
    path = with_axis(model10, RECORD).save(tmp_path / "m.json")
    loaded = FrictionModel.load(path)
    assert loaded.axis == Axis(**RECORD)
    assert loaded.axis.to_dict() == RECORD
    assert loaded.model_hash == model10.model_hash
    assert np.array_equal(loaded.force([0.01, -0.2]), model10.force([0.01, -0.2]))


def test_a_hand_edited_axis_record_is_used_with_one_warning_naming_its_hash(model10, tmp_path, capsys):
    path = with_axis(model10, RECORD).save(tmp_path / "m.json")
    written = json.loads(path.read_text())
    assert written["axis_hash"] == FrictionModel.load(path).axis_hash
    assert main(["simulate", "--model", str(path), "--duration", "0.1", "--json"]) == 0
    assert capsys.readouterr().err == ""
    written["training"]["axis"]["mass"] = 9.51          # a plausible mass, a digit lost
    path.write_text(json.dumps(written))
    edited = FrictionModel.load(path)
    assert edited.model_hash == model10.model_hash and edited.edited_after_training
    assert main(["simulate", "--model", str(path), "--duration", "0.1", "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["plant"].startswith("plant: the model's axis, m = 9.51 kg")
    warning = captured.err.strip().splitlines()
    assert len(warning) == 1 and "edited after training (axis_hash" in warning[0]
    assert "model_hash" not in warning[0]


def test_a_model_without_the_record_has_no_axis(model10, tmp_path):
    assert FrictionModel.load(model10.save(tmp_path / "m.json")).axis is None
    assert with_axis(model10, None).axis is None          # "axis": null, as absent


BAD_RECORDS = [
    ("negative mass", {"mass": -1.0}, "training.axis.mass must be > 0"),
    ("zero mass", {"mass": 0}, "training.axis.mass must be > 0"),
    ("infinite mass", {"mass": "INF"}, "training.axis.mass must be finite"),
    ("mass as text", {"mass": "95"}, "training.axis.mass must be a number, got str"),
    ("negative mass_se", {"mass_se": -0.1}, "training.axis.mass_se must be >= 0"),
    ("mass_se of a given mass", {"mass_from": "option"}, "training.axis.mass_se must be null"),
    ("unknown mass_from", {"mass_from": "guess"}, "training.axis.mass_from must be one of"),
    ("mass_from without mass", {"mass": None, "mass_se": None}, "training.axis.mass_from must be null"),
    ("zero force constant", {"force_constant": 0.0}, "training.axis.force_constant must be > 0"),
    ("offset_se without offset", {"offset": None}, "training.axis.offset_se must be null"),
    ("speed_max below speed_min", {"speed_max": 0.0005}, "training.axis.speed_max (0.0005 m/s) must be >="),
    ("negative speed_min", {"speed_min": -0.1}, "training.axis.speed_min must be >= 0"),
    ("boolean speed_max", {"speed_max": True}, "training.axis.speed_max must be a number, got bool"),
    ("unknown key", {"masss": 1.0}, "unknown field 'training.axis.masss'"),
    ("null speed_max", {"speed_max": None}, "training.axis.speed_max must be a number, got NoneType"),
    ("mass of no real axis", {"mass": 1e9}, "training.axis.mass is 1e+09 kg, above the 100000 kg"),
    ("speed_max of no real axis", {"speed_max": 50.0},
     "training.axis.speed_max is 50 m/s, above the 20 m/s of any real axis"),
    ("offset of no real axis", {"offset": -1e6}, "training.axis.offset is 1e+06 N, above the 100000 N"),
]


def test_an_unusual_record_loads_when_the_model_was_trained_to_accept_it(model10):
    edited = with_axis(model10, {**RECORD, "mass": 1e9, "offset": 0.0, "offset_se": 0.0})
    with pytest.raises(ModelError, match="an edited record"):
        FrictionModel.from_dict(edited.to_dict())
    unusual = dataclasses.replace(edited, training={**edited.training, "accept_unusual": True})
    assert FrictionModel.from_dict(unusual.to_dict()).axis.mass == 1e9


@pytest.mark.parametrize("edit, message", [row[1:] for row in BAD_RECORDS],
                         ids=[row[0] for row in BAD_RECORDS])
def test_a_bad_record_is_refused_with_one_line_naming_the_field(model10, tmp_path, capsys, edit,
                                                                message):
    record = {**RECORD, **edit}
    text = json.dumps(with_axis(model10, record).to_dict()).replace('"INF"', "1e999")
    (tmp_path / "m.json").write_text(text)
    assert main(["emit", str(tmp_path / "m.json"), "-o", str(tmp_path / "out"), "--dtype", "q15"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "out").exists()


def test_a_record_that_is_not_an_object_or_lacks_a_field_is_refused(model10):
    with pytest.raises(ModelError, match="training.axis must be an object"):
        FrictionModel.from_dict(with_axis(model10, [1, 2]).to_dict())
    record = {k: v for k, v in RECORD.items() if k != "offset"}
    with pytest.raises(ModelError, match="training.axis: missing field 'offset'"):
        FrictionModel.from_dict(with_axis(model10, record).to_dict())


# ----------------------------------------------------------------------------- simulate


def test_simulate_runs_the_models_axis_and_keeps_the_reference_within_its_speeds(model10):
    plant = choose_plant(with_axis(model10, RECORD))
    law = plant.axis.law
    assert law.mass == 95.1 and law.friction.model_hash == model10.model_hash
    assert law.external_force(np.zeros(1), np.zeros(1), np.zeros(1))[0] == pytest.approx(-3.16)  # = offset
    # the axis's own motor (the force constant training read the current with), known to the
    # controller, with the built-in's thrust per kg
    assert law.force_constant == plant.phi_n == RECORD["force_constant"]
    assert law.force_constant * law.i_max == pytest.approx(90.0 * 95.1) and plant.i_max == law.i_max
    assert f"motor 1 N/A (the model's axis), {law.i_max:.4g} A" in plant.text
    plain = choose_plant(with_axis(model10, {**RECORD, "force_constant": None}))
    assert plain.phi_n / plain.axis.law.force_constant == pytest.approx(20 / 18)  # scaled built-in
    speeds = np.abs(sampled(plant.trajectory, np.arange(0, 4.0, 1e-3))[:, 1])
    assert 0.9 * RECORD["speed_max"] < speeds.max() <= RECORD["speed_max"]
    assert plant.text.startswith("plant: the model's axis, m = 95.1 kg (identified from the data)")


@pytest.mark.parametrize("record, argv, wanted, mass", [
    (RECORD, [], "plant: the model's axis, m = 95.1 kg (identified from the data)", 95.1),
    (RECORD, ["--mass", "7"], "plant: the model's axis, m = 7 kg (--mass)", 7.0),
    (None, [], "plant: built-in 2 kg axis (Table 1 friction); the model carries no axis", 2.0),
    (SWEEP, [], "plant: built-in 2 kg axis (Table 1 friction); the model's axis has no mass", 2.0),
], ids=["axis", "--mass overrides", "no axis", "sweep axis"])
def test_simulate_says_which_plant_it_runs(model10, tmp_path, capsys, record, argv, wanted, mass):
    model = with_axis(model10, record) if record is not None else model10
    path = model.save(tmp_path / "m.json")
    assert main(["simulate", "--model", str(path), "--duration", "0.1", "--json", *argv]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["plant"].startswith(wanted), report["plant"]
    assert choose_plant(model, float(argv[1]) if argv else None).axis.law.mass == mass
    variants = set(report["variants"])
    assert variants == ({"none", "model"} if mass != 2.0 else {"none", "exact", "model"})
    assert all(v["finite"] for v in report["variants"].values())


def test_simulate_compensates_the_axis_offset_with_the_friction_in_python_and_c(model10, tmp_path):
    import shutil
    from fricgen.control import AdaptiveBackstepping
    from fricgen.control.c_controller import c_controllers
    from fricgen.control.loop import compensations
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        pytest.skip("no C compiler")
    model = with_axis(model10, RECORD)
    variants = compensations(choose_plant(model).axis, model)
    v = np.linspace(-0.12, 0.12, 25)
    np.testing.assert_allclose(variants["model"](v), model.force(v) + RECORD["offset"], rtol=0, atol=1e-12)
    ctrl = c_controllers(variants, AdaptiveBackstepping(), folder=tmp_path / "c")["model"]
    assert ctrl.c_friction == "model_force_with_offset"
    c = np.array([ctrl.module.lib.model_force_with_offset(float(u)) for u in v])
    assert np.max(np.abs(c - variants["model"](v))) <= 1e-5 * np.max(np.abs(model.force(v)))
    plain = with_axis(model10, {**RECORD, "offset": None, "offset_se": None})   # none identified
    assert compensations(choose_plant(plain).axis, plain)["model"] is plain


def test_simulate_speaks_the_rotary_units_of_a_joints_model(model10, tmp_path, capsys):
    joint = dataclasses.replace(model10, training={**model10.training, "units": "rotary", "axis": RECORD})
    assert main(["simulate", "--model", str(joint.save(tmp_path / "j.json")), "--duration", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "m = 95.1 kg m^2 (identified from the data), offset -3.16 Nm as a constant force" in out
    assert "motor 1 Nm/A" in out and " rad/s" in out and "rms_e1 mrad" in out and "A s/rad" in out
    assert " m/s" not in out and " mm " not in out and "kg (" not in out
    assert main(["emit", str(tmp_path / "j.json"), "-o", str(tmp_path / "c")]) == 0
    header = (tmp_path / "c" / "fm.h").read_text()
    assert "Friction force in Nm at velocity v (rad/s)" in header and "newtons" not in header


def test_simulate_keeps_the_builtin_speeds_for_a_model_trained_faster(model10):
    fast = {**SWEEP, "speed_max": 1.0}
    plant = choose_plant(with_axis(model10, fast))
    assert plant.trajectory == reversing(*DEFAULT_SPEEDS)
    assert "reference peak speeds 0.02 to 0.2 m/s (the model was trained up to 1 m/s)" in plant.text


def test_simulate_mass_without_a_model_is_refused(capsys):
    assert main(["simulate", "--mass", "5", "--duration", "0.1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--mass sets the mass of the model's axis: it needs --model" in err


# ----------------------------------------------------------------------------- diagnose


@pytest.fixture(scope="module")
def diag_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("diag_axis")
    model = nominal_model()
    log = synthesize_log(LogSpec(effect="constant_load", duration=6.0), model)
    (folder / "log.csv").write_text(log_csv_text(log))
    # no offset: an asymmetric model's curves hold it (diagnose would carry a recorded one)
    record = {**RECORD, "mass": 4.0, "force_constant": 20.0, "offset": None, "offset_se": None}
    with_axis(model, record).save(folder / "axis.json")
    with_axis(model, SWEEP).save(folder / "sweep.json")
    model.save(folder / "plain.json")
    return folder


@pytest.mark.slow
def test_diagnose_takes_mass_and_force_constant_from_the_axis(diag_files, tmp_path, capsys):
    log = str(diag_files / "log.csv")
    assert main(["diagnose", log, "--model", str(diag_files / "axis.json"), "--json",
                 "-o", str(tmp_path / "a")]) == 0
    from_axis = capsys.readouterr()
    assert "fricgen: mass from the model's axis: m = 4 kg (identified from the data)" in from_axis.err
    assert "fricgen: force constant from the model's axis: phi = 20 N/A" in from_axis.err
    assert FrictionModel.load(tmp_path / "a" / "model.json").axis.mass == 4.0   # kept
    assert main(["diagnose", log, "--model", str(diag_files / "plain.json"), "--json",
                 "--mass", "4", "--force-constant", "20", "-o", str(tmp_path / "b")]) == 0
    assert json.loads(from_axis.out) == json.loads(capsys.readouterr().out)
    # an option overrides the axis: another mass, another diagnosis input
    assert main(["diagnose", log, "--model", str(diag_files / "axis.json"), "--json", "--mass",
                 "6", "-o", str(tmp_path / "c")]) == 0
    err = capsys.readouterr().err
    assert "mass from the model's axis" not in err and "force constant from the model's axis" in err


@pytest.mark.parametrize("model, argv, message", [
    ("plain.json", [], "--mass is required: the model's axis record gives no mass (it has none)"),
    ("sweep.json", ["--force-constant", "20"],
     "--mass is required: the model's axis record gives no mass (it was trained on a sweep)"),
    ("sweep.json", ["--mass", "4"], "--force-constant is required: the model's axis record gives none"),
], ids=["no axis", "sweep axis", "no force constant"])
def test_diagnose_without_a_mass_anywhere_is_refused(diag_files, tmp_path, capsys, model, argv,
                                                     message):
    assert main(["diagnose", str(diag_files / "log.csv"), "--model", str(diag_files / model),
                 *argv, "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err == f"fricgen: error: {message}\n"
    assert not (tmp_path / "out").exists()


# ----------------------------------------------------------------------------- emit


def test_q15_covers_the_models_training_speeds_within_the_headers_bound(model10, tmp_path, capsys):
    """v_sat = 0.06 m/s alone gives |v| < 0.125 m/s; the axis' 0.2 m/s widens it to 0.25."""
    assert model10.v_sat == pytest.approx(0.06)
    model = with_axis(model10, SWEEP)
    folder = tmp_path / "q15"
    assert main(["emit", str(model.save(tmp_path / "m.json")), "-o", str(folder), "--dtype", "q15",
                 "--name", "fm"]) == 0
    assert "the q15 C takes |v| < 0.25 m/s, covering 0.2 m/s (the model's axis" in capsys.readouterr().err
    header = (folder / "fm.h").read_text()
    assert "(|v| < 0.25 m/s, which covers\n * 0.2 m/s, the fastest speed of the model's training data" in header
    spec = fx.FixedSpec.of(model, "q15")
    bound = fx.error_bound(spec, model)
    assert f"<= {bound:.3g} N" in header
    lib = cbuild.build(folder, "fm.h", "int16_t fm_force_q15(int16_t v_q);", build_dir=folder / "build")
    for v in (0.2, -0.2, 0.15, 0.06):
        v_q = int(round(v * 2.0 ** spec.f_v))
        force = lib.fm_force_q15(v_q) * 2.0 ** -spec.f_f
        assert abs(force - float(model.force(v_q * 2.0 ** -spec.f_v))) <= bound, v


@pytest.mark.parametrize("record, argv, v_range, note", [
    (None, [], 0.125, "fricgen: warning: the q31 C takes |v| < 0.125 m/s (2 v_sat): faster speeds "
                      "clamp there; the model records no speed range (--v-max sets one)"),
    (None, ["--v-max", "0.3"], 0.5, "fricgen: the q31 C takes |v| < 0.5 m/s, covering 0.3 m/s (--v-max)"),
    (SWEEP, ["--v-max", "0.1"], 0.125, "covering 0.1 m/s (--v-max)"),
], ids=["no range: warned", "--v-max", "--v-max overrides the axis"])
def test_emit_says_which_speeds_fixed_point_covers(model10, tmp_path, capsys, record, argv,
                                                   v_range, note):
    model = with_axis(model10, record) if record is not None else model10
    assert main(["emit", str(model.save(tmp_path / "m.json")), "-o", str(tmp_path / "c"),
                 "--dtype", "q31", *argv]) == 0
    assert note in capsys.readouterr().err
    v_max = float(argv[1]) if argv else None
    assert fx.input_range(model, "q31", v_max) == v_range
    assert 2.0 ** (31 - fx.FixedSpec.of(model, "q31", v_max).f_v) == v_range


def test_emit_says_where_the_axis_offset_is_unless_an_effect_carries_it(model10, tmp_path, capsys):
    model = with_axis(model10, RECORD)
    assert main(["emit", str(model.save(tmp_path / "m.json")), "-o", str(tmp_path / "c")]) == 0
    assert ("the axis's offset o = -3.16 N (training.axis.offset) is not in fm_force, the friction "
            "alone; fm_force_with_offset adds it") in capsys.readouterr().err
    carried = with_effects(model, [ConstantLoad(load=-3.16)])
    assert main(["emit", str(carried.save(tmp_path / "e.json")), "-o", str(tmp_path / "e")]) == 0
    assert "is not in fm_force" not in capsys.readouterr().err


def test_v_max_with_float_is_refused(model10, tmp_path, capsys):
    assert main(["emit", str(model10.save(tmp_path / "m.json")), "-o", str(tmp_path / "c"),
                 "--v-max", "0.3"]) == 2
    err = capsys.readouterr().err
    assert err == ("fricgen: error: --v-max sets the input range of --dtype q15 or q31; float "
                   "takes any speed\n")
    assert not (tmp_path / "c").exists()


def test_simulate_warns_when_the_reference_asks_more_than_the_motor_gives(model10, tmp_path, capsys):
    """A 0.05 kg axis with ~44 N of friction: the mass-scaled motor gives 4.5 N."""
    path = model10.save(tmp_path / "m.json")
    assert main(["simulate", "--model", str(path), "--mass", "0.05", "--duration", "0.1"]) == 0
    err = capsys.readouterr().err
    assert "more than the simulated motor's 4.5 N: the current saturates" in err
    assert main(["simulate", "--model", str(path), "--mass", "5", "--duration", "0.1"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_q15_bound_holds_over_all_65536_inputs_of_a_sweep_to_10_v_sat(model10, tmp_path):
    """The header's error bound holds for every q15 input of the declared range when the axis
    reaches 10 v_sat (the range then is 1 m/s for v_sat = 0.06 m/s); the header says the range,
    that faster speeds are clamped to it, and that the output saturates."""
    record = {**SWEEP, "speed_max": 10 * model10.v_sat}
    model = with_axis(model10, record)
    spec = fx.FixedSpec.of(model, "q15")
    v_range = 2.0 ** (15 - spec.f_v)
    assert v_range >= 10 * model10.v_sat
    v_q = np.arange(-2 ** 15, 2 ** 15, dtype=np.int64)
    error = np.abs(fx.force_q(spec, v_q) * 2.0 ** -spec.f_f - model.force(v_q * 2.0 ** -spec.f_v))
    bound = fx.error_bound(spec, model)
    assert float(error.max()) <= bound
    folder = tmp_path / "q15"
    assert main(["emit", str(model.save(tmp_path / "m.json")), "-o", str(folder), "--dtype", "q15",
                 "--name", "fm"]) == 0
    header = (folder / "fm.h").read_text()
    assert f"|v| < {v_range:g} m/s" in header and f"<= {bound:.3g} N" in header
    assert "clamp faster speeds to the range" in header and "saturated" in header
