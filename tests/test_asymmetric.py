"""The asymmetric model: one curve of [F3] per direction, model.json format version 2, its C."""
import copy
import json

import numpy as np
import pytest

from conftest import assert_builds_strictly
from fricgen import codegen
from fricgen.codegen import parity
from fricgen.c_literal import c_float
from fricgen.codegen.cbuild import build, build_model, model_cdef
from fricgen.codegen.fast_sigmoid import aim_fast_f32
from fricgen.codegen.twin import force_f32, stribeck_aim_f32
from fricgen.data import Sweep, prepare, synthesize_benchmark
from fricgen.errors import DataError, ModelError
from fricgen.cli import main
from fricgen.fit import ELMRegressor, StribeckRegressor
from fricgen.fit.directions import fit_directions
from fricgen.fit.elm import EnlargedScheme
from fricgen.firmware import build as fw
from fricgen.friction import multisource, preset
from fricgen.model import Direction, FrictionModel
from fricgen.networks import StribeckCurve
from fricgen.sim.effect_law import EffectLaw
from test_references import TABLE1, float32_bound, table1_curve

CC = "cc"
EPS32 = float(np.finfo(np.float32).eps)


def _elm10():
    return ELMRegressor(n_hidden=10, scheme=EnlargedScheme(w_max=30.0), solver="loo", random_state=0)


@pytest.fixture(scope="module")
def asym(model10):
    """model10's curve for v >= 0, and for v < 0 a curve fitted to the exponential-Stribeck
    variant of the benchmark with 30 % more friction."""
    other = synthesize_benchmark(preset("paper3", "exponential"), seed=1)
    scaled = Sweep(other.train.v, 1.3 * other.train.f)
    negative = Direction.fit(prepare(scaled, vs_max=0.02), _elm10())
    return FrictionModel.from_directions(model10.positive, negative, name="fa")


def test_each_direction_has_its_own_curve(asym, model10):
    v = np.linspace(0.0, 0.2, 101)
    np.testing.assert_array_equal(asym.force(v), model10.force(v))
    np.testing.assert_allclose(asym.force(-v[1:]), -asym.negative.magnitude(v[1:]), rtol=1e-15)
    assert np.all(-asym.force(-v[1:]) > asym.force(v[1:]))      # 30 % more friction for v < 0
    assert not asym.symmetric and model10.symmetric


def test_version_2_round_trips_and_symmetric_models_stay_version_1(asym, model10, tmp_path):
    d = json.loads(asym.to_json())
    assert d["format_version"] == 2 and d["symmetric"] is False and set(d["negative"]) == {
        "aim", "scaling", "viscous", "v_sat"}
    back = FrictionModel.load(asym.save(tmp_path / "a.json"))
    v = np.linspace(-0.3, 0.3, 1001)
    np.testing.assert_array_equal(back.force(v), asym.force(v))
    assert back.model_hash == asym.model_hash != model10.model_hash
    one = json.loads(model10.to_json())
    assert one["format_version"] == 1 and "negative" not in one
    v1 = FrictionModel.load(model10.save(tmp_path / "s.json"))
    np.testing.assert_array_equal(v1.force(v), model10.force(v))
    assert v1.model_hash == model10.model_hash


def _mutations():
    yield "no negative", lambda d: d.pop("negative"), "missing or invalid field 'negative'"
    yield "negative a list", lambda d: d.__setitem__("negative", []), "field 'negative'"
    yield "unknown field", lambda d: d["negative"].__setitem__("effects", []), "negative.effects"
    yield "negative nan B", lambda d: d["negative"].__setitem__("viscous", float("nan")), "negative: "
    yield "negative v_sat 0", lambda d: d["negative"].__setitem__("v_sat", 0), "must be > 0"
    yield "negative bad kind", lambda d: d["negative"]["aim"].__setitem__("kind", "svm"), "aim.kind"
    yield "negative no scaling", lambda d: d["negative"].pop("scaling"), "negative: missing"
    yield "symmetric a string", lambda d: d.__setitem__("symmetric", "no"), "true or false"
    yield "negative in a symmetric model", lambda d: d.__setitem__("symmetric", True), \
        "says symmetric: true, yet holds a curve .negative. of v < 0"
    yield "negative in version 1", lambda d: d.__setitem__("format_version", 1), "symmetric must be true"
    yield "version 3 without inputs", lambda d: d.__setitem__("format_version", 3), "no field 'inputs': an edited format_version"


@pytest.mark.parametrize("label, mutate, message", list(_mutations()), ids=[m[0] for m in _mutations()])
def test_invalid_version_2_is_named(asym, label, mutate, message):
    d = json.loads(asym.to_json(), parse_constant=float)
    mutate(d)
    with pytest.raises(ModelError, match=message):
        FrictionModel.from_dict(json.loads(json.dumps(d)))


def test_version_1_with_negative_is_refused(model10):
    d = json.loads(model10.to_json())
    d["negative"] = copy.deepcopy({k: d[k] for k in ("aim", "scaling", "viscous", "v_sat")})
    with pytest.raises(ModelError, match="needs format_version 2"):
        FrictionModel.from_dict(d)


def test_each_direction_may_hold_any_network_kind(asym):
    curve = StribeckCurve("gauss", 0.5, np.array([0.4]), np.array([0.2]), 0.1)
    mixed = FrictionModel.from_directions(asym.positive, Direction(curve, asym.negative.scaling,
                                                                   asym.negative.viscous, asym.negative.v_sat))
    back = FrictionModel.from_dict(json.loads(mixed.to_json()))
    v = np.linspace(-0.2, 0.2, 401)
    np.testing.assert_array_equal(back.force(v), mixed.force(v))
    assert back.negative.aim.kind == "stribeck"


def test_simulator_and_diagnosis_law_use_the_asymmetric_force(asym):
    law = EffectLaw(asym, mass=4.0, force_constant=20.0)
    v = np.linspace(-0.2, 0.2, 401)
    np.testing.assert_array_equal(law.sliding_friction(v, 0.0 * v, np.abs(v)), asym.force(v))


def _curve_tolerance(curve, speed):
    """The libm bound of one curve at the speeds ``speed``: a few ULP of each term of [F7]
    (as test_codegen) or [F1], and of B |v|."""
    net = curve.aim
    if isinstance(net, StribeckCurve):
        terms, n = abs(net.offset) + abs(net.slope) + np.abs(net.amplitudes).sum(), net.n_sources
    else:
        terms = np.abs(net.hidden(curve.network_input(speed)) * net.output_weights).sum(axis=1)
        n = net.n_hidden
    return (n + 3) * EPS32 * (terms / curve.scaling.k_out + np.abs(curve.viscous * speed))


def _assert_c_matches_twin(lib, name, model, impl, exact_rel):
    """The C of ``model`` over the parity velocities of both directions: bit-equal to the float32
    twin with the fast exponential, within the twin's rounding tolerance (and equal on > 99 %)
    with libm; within ``exact_rel`` of max |F| of the float64 model. Returns (v, C forces)."""
    v = parity.parity_velocities(max(d.v_sat for d in model.directions))
    c = parity.c_forces(lib, name, v).astype(float)
    twin = force_f32(model, v, impl).astype(float)
    if impl == "fast":
        assert np.array_equal(c, twin)
    else:
        assert np.all(np.abs(c - twin) <= _twin_tolerance(model, v.astype(float)))
        assert np.mean(c == twin) > 0.99
    exact = model.force(v.astype(float))
    assert np.max(np.abs(c - exact)) <= exact_rel * np.max(np.abs(exact))
    return v, c


def _twin_tolerance(model, v):
    """The per-velocity bound for the curve of each velocity's direction."""
    bound = np.zeros_like(v)
    for rows, curve in zip((v >= 0, v < 0), model.directions):
        bound[rows] = _curve_tolerance(curve, np.abs(v[rows]))
    return bound + 1e-30


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_c_matches_float32_twin_and_float64_model(asym, tmp_path, impl):
    codegen.emit(asym, tmp_path, "fa", activation_impl=impl)
    h = (tmp_path / "fa.h").read_text()
    assert "#define FA_ASYMMETRIC 1" in h and "#define FA_FORMAT_VERSION 2" in h
    lib = build_model(tmp_path, "fa", build_dir=tmp_path / "build")
    _assert_c_matches_twin(lib, "fa", asym, impl, exact_rel=1e-5)
    assert lib.fa_force(0.0) == 0.0 and lib.fa_force(-0.01) != -lib.fa_force(0.01)
    edges = [float("nan"), float("inf"), -float("inf")]
    out = [lib.fa_force(e) for e in edges]
    assert np.isnan(out[0]) and out[1] == np.inf and out[2] == -np.inf


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_asymmetric_c_builds_without_a_single_warning(asym, tmp_path, impl):
    codegen.emit(asym, tmp_path, "fa", activation_impl=impl)
    for src in sorted(p.name for p in tmp_path.glob("*.c")):
        assert_builds_strictly(tmp_path, src, CC)


def test_symmetric_model_emits_the_same_c_as_before(model10):
    files = codegen.render(model10, "fm")
    assert "negative" not in files["fm.c"] and "ASYMMETRIC" not in files["fm.h"]
    assert "#define FM_FORMAT_VERSION 1" in files["fm.h"]


def test_fixed_point_refuses_an_asymmetric_elm_model(asym):
    with pytest.raises(ModelError, match="curves are both grey-box"):
        codegen.render(asym, "fa", dtype="q15")


def _two_directions(scale_negative, seed=0):
    """A sweep of paper3 in both directions, the negative one's force scaled."""
    pos = synthesize_benchmark(preset("paper3"), seed=seed).train
    neg = synthesize_benchmark(preset("paper3"), seed=seed + 100).train
    return Sweep(np.concatenate([pos.v, -neg.v]), np.concatenate([pos.f, -scale_negative * neg.f]))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_symmetric_data_keep_the_symmetric_model(seed):
    fitted = fit_directions(_two_directions(1.0, seed), _elm10(), vs_max=0.02, seed=seed)
    assert not fitted.asymmetric and fitted.chosen_by == "cross-validation"
    assert fitted.cv_rmse[0] <= fitted.cv_rmse[1] * 1.01


def test_asymmetric_data_pick_the_asymmetric_model():
    fitted = fit_directions(_two_directions(1.2), _elm10(), vs_max=0.02)
    assert fitted.asymmetric and fitted.cv_rmse[1] < 0.8 * fitted.cv_rmse[0]
    pos, neg = (f.curve for f in fitted.fits)
    speed = np.linspace(0.001, 0.06, 50)
    ratio = neg.magnitude(speed) / pos.magnitude(speed)
    assert np.all(np.abs(ratio - 1.2) < 0.05)


def test_forced_choices_and_one_direction(bench):
    sweep = _two_directions(1.0)
    assert fit_directions(sweep, _elm10(), vs_max=0.02, asymmetric=True).asymmetric
    assert not fit_directions(_two_directions(1.2), _elm10(), vs_max=0.02, asymmetric=False).asymmetric
    one = fit_directions(bench.train, _elm10(), vs_max=0.02)
    assert not one.asymmetric and one.chosen_by == "one direction only"
    with pytest.raises(DataError, match="needs a sweep of each direction"):
        fit_directions(bench.train, _elm10(), vs_max=0.02, asymmetric=True)


@pytest.mark.skipif(fw.missing_tools() is not None, reason="cross toolchain or QEMU absent")
@pytest.mark.parametrize("target", sorted(fw.TARGETS))
def test_emulated_asymmetric_fast_model_is_bit_equal_to_python_twin(asym, target, tmp_path):
    v_sat = max(c.v_sat for c in asym.directions)
    v = np.concatenate([np.linspace(-2 * v_sat, 2 * v_sat, 101, dtype=np.float32),
                        np.array([0.0, -0.0, 1e3, -1e3], dtype=np.float32)])
    codegen.emit(asym, tmp_path / "model", "fm", activation_impl="fast", with_controller=True)
    cfg = fw.config_float("fm.h", "fm_force", v, n_bench=4)
    elf = fw.build_firmware(tmp_path / "model", cfg, target, tmp_path / "build")
    out = fw.parse_float_bits(fw.run(elf, target))
    assert np.array_equal(out.view(np.uint32), force_f32(asym, v, "fast").view(np.uint32))


def _table1_like(scale_force, scale_vs, scale_b, shape="gauss"):
    """Table 1 with every f_c and f_s times ``scale_force``, v_s times ``scale_vs``, B times ``scale_b``."""
    return multisource([scale_force * s.fc for s in preset("paper3").sources],
                       [scale_force * s.fs for s in preset("paper3").sources],
                       [scale_vs * s.vs for s in preset("paper3").sources],
                       [scale_b * s.B for s in preset("paper3").sources], shape)


@pytest.fixture(scope="module")
def curves():
    """Grey-box [F1] and ELM curves of two directions that differ in every constant of
    [F3]: v >= 0 fitted to Table 1 (vs_max 0.02), v < 0 to Table 1 with 30 % more friction,
    Stribeck velocities 1.5 x (vs_max 0.03) and 0.6 B, of the exponential shape."""
    data = {1: synthesize_benchmark(preset("paper3"), seed=0).dataset,
            -1: synthesize_benchmark(_table1_like(1.3, 1.5, 0.6, "exponential"), seed=1).dataset}
    return {(kind, sign): Direction.fit(d, StribeckRegressor() if kind == "stribeck" else _elm10())
            for sign, d in data.items() for kind in ("stribeck", "elm")}


#: The (v >= 0, v < 0) curve kinds of the asymmetric models whose C is checked: grey-box in both
#: directions, and each mixture (each direction chose its own model).
KINDS = [("stribeck", "stribeck"), ("stribeck", "elm"), ("elm", "stribeck")]


def _model(curves, kinds):
    return FrictionModel.from_directions(curves[kinds[0], 1], curves[kinds[1], -1], name="fb")


def test_the_two_directions_differ_in_every_constant_of_eq3(curves):
    pos, neg = curves["stribeck", 1], curves["stribeck", -1]
    for a, b in ((pos.v_sat, neg.v_sat), (pos.scaling.k_in, neg.scaling.k_in),
                 (pos.scaling.k_out, neg.scaling.k_out), (pos.viscous, neg.viscous)):
        assert abs(a - b) > 0.1 * max(abs(a), abs(b))
    model = FrictionModel.from_directions(pos, neg, name="fb")
    laws = {1: preset("paper3"), -1: _table1_like(1.3, 1.5, 0.6, "exponential")}
    for sign, curve in ((1, pos), (-1, neg)):       # each follows its own law, not the other's
        v = sign * np.linspace(0.0005, curve.v_sat, 400)
        own, other = (np.sqrt(np.mean((model.force(v) - laws[s](v)) ** 2)) for s in (sign, -sign))
        assert own < 0.2 and other > 20 * own


def _aim_twin(curve, x, impl):
    net = curve.aim
    if isinstance(net, StribeckCurve):
        return stribeck_aim_f32(net, x, impl)
    return aim_fast_f32(net, x) if impl == "fast" else net.float32(x)


@pytest.mark.parametrize("impl", ["libm", "fast"])
@pytest.mark.parametrize("kinds", KINDS, ids=["+".join(k) for k in KINDS])
def test_grey_box_and_mixed_asymmetric_c_matches_its_twin_and_the_model(curves, kinds, impl, tmp_path):
    model = _model(curves, kinds)
    pos, neg = model.directions
    codegen.emit(model, tmp_path, "fb", activation_impl=impl)
    for src in sorted(p.name for p in tmp_path.glob("*.c")):
        assert_builds_strictly(tmp_path, src, CC)
    h = (tmp_path / "fb.h").read_text()
    for curve, suffix in ((pos, ""), (neg, "_NEGATIVE")):
        size = ("N_SOURCES", curve.aim.n_sources) if curve.aim.kind == "stribeck" else (
            "N_HIDDEN", curve.aim.n_hidden)
        assert f"#define FB_{size[0]}{suffix} {size[1]}\n" in h
    assert "#define FB_ASYMMETRIC 1" in h
    assert f"#define FB_V_SAT {c_float(pos.v_sat)}\n" in h
    assert f"#define FB_V_SAT_NEGATIVE {c_float(neg.v_sat)}\n" in h
    cdef = model_cdef("fb") + "float fb_aim_negative(float x);\n"
    lib = build(tmp_path, "fb.h", cdef, build_dir=tmp_path / "build")
    x = np.linspace(0.0, 1.0, 1001, dtype=np.float32)
    for fn, curve in ((lib.fb_aim, pos), (lib.fb_aim_negative, neg)):
        c_aim = np.array([fn(float(u)) for u in x], dtype=np.float32)
        twin_aim = _aim_twin(curve, x, impl)
        if impl == "fast":                                  # no libm: bit for bit
            assert np.array_equal(c_aim, twin_aim)
        else:                                               # expf within 1 ULP
            assert np.max(np.abs(c_aim - twin_aim)) <= 4 * EPS32 * np.max(np.abs(twin_aim))
    v, c = _assert_c_matches_twin(lib, "fb", model, impl, exact_rel=1e-7)   # 2.6e-8 measured
    inside = np.abs(v) <= min(pos.v_sat, neg.v_sat)
    assert np.all(c[inside & (v > 0)] > 0) and np.all(c[inside & (v < 0)] < 0)
    assert lib.fb_force(0.0) == 0.0 and lib.fb_force(-0.01) != -lib.fb_force(0.01)
    out = [lib.fb_force(e) for e in (float("nan"), float("inf"), -float("inf"))]
    assert np.isnan(out[0]) and out[1] == np.inf and out[2] == -np.inf


@pytest.mark.parametrize("kinds", KINDS, ids=["+".join(k) for k in KINDS])
def test_fixed_point_emits_a_grey_box_pair_and_refuses_an_asymmetric_model_with_an_elm(curves, kinds):
    if kinds == ("stribeck", "stribeck"):                   # a table per direction
        files = codegen.render(_model(curves, kinds), "fb", dtype="q31")
        assert "fb_aim_positive[" in files["fb.c"] and "fb_aim_negative[" in files["fb.c"]
        return
    with pytest.raises(ModelError, match="curves are both grey-box"):
        codegen.render(_model(curves, kinds), "fb", dtype="q31")


def test_default_train_keeps_the_better_model_per_direction_and_it_emits(tmp_path, capsys):
    """The default (grey-box [F1] or elm_auto) fits each direction of an asymmetric sweep;
    the report names each direction's choice and its estimated vs_max, and ``emit`` writes its
    C. (--asymmetric spares the test the cross-validation of the symmetry.)"""
    sweep = _two_directions(1.2)
    csv = tmp_path / "both.csv"
    np.savetxt(csv, np.column_stack([sweep.v, sweep.f]), delimiter=",", header="v,f", comments="")
    model_json = tmp_path / "m.json"
    assert main(["train", str(csv), "--asymmetric", "-o", str(model_json)]) == 0
    report = capsys.readouterr().out
    assert report.count("  chose     ") == 2 and report.count("  outliers  ") == 2
    assert report.count("(vs_max chosen from the data; pass --vs-max to set it)") == 2
    model = FrictionModel.load(model_json)
    training = json.loads(model_json.read_text())["training"]
    kinds = [c.aim.kind for c in model.directions]
    assert [training["choice"], training["negative"]["choice"]] == [
        "elm_auto" if k == "elm" else k for k in kinds]
    assert "stribeck" in kinds                       # Table 1 data: [F1] wins somewhere
    assert main(["emit", str(model_json), "-o", str(tmp_path / "c")]) == 0
    assert "_aim_negative" in (tmp_path / "c" / "friction_model.c").read_text()


#: v < 0 of the literal asymmetric model: Table 1 with f_c, f_s x 1.3, v_s x 1.5 and B x 0.6
#: (34.5 N s/m), exponential: v_sat = 0.09 m/s and K_in = 1/0.09 against 0.06 and 1/0.06 for
#: v >= 0 (Table 1, gauss). F by hand at |v| = 0.075 (v >= 0 saturated, v < 0 not), 0.12 (both):
#: v >= 0: (18.4518511470613 - 57.5 * 0.06) + 57.5 |v|, held from 0.06 on;
#: v < 0: 19.5 + 5.2 e^-5 + 13 e^-10 + 19.5 e^-2.5 + 34.5 * 0.075 = 23.723784996648185, and
#: (23.588817219252608 - 34.5 * 0.09) + 34.5 * 0.12 = 24.623817219252607 held from 0.09 on.
SCALED_TABLE1 = tuple((1.3 * fc, 1.3 * fs, 1.5 * vs, 0.6 * b) for fc, fs, vs, b in TABLE1)
BETWEEN_SATURATIONS = np.array([(0.075, 15.0018511470613 + 57.5 * 0.075),
                                (-0.075, -23.723784996648185),
                                (0.12, 15.0018511470613 + 57.5 * 0.12),
                                (-0.12, -24.623817219252607)])


@pytest.fixture(scope="module")
def literal_asym():
    negative = table1_curve("exponential", SCALED_TABLE1, k_out=1.0 / 57.2, v_sat=0.09).positive
    return FrictionModel.from_directions(table1_curve("gauss").positive, negative, name="fl")


@pytest.mark.parametrize("impl", ["libm", "fast"])
def test_each_direction_saturates_at_its_own_v_sat_in_c_and_the_twin(literal_asym, impl, tmp_path):
    """Between the two saturation points (0.06 < |v| < 0.09) and beyond both, the model, its
    float32 twin and the C give the hand-computed forces: each branch uses its own v_sat,
    K_in, K_out and B."""
    pos, neg = literal_asym.directions
    assert (pos.v_sat, neg.v_sat) == (0.06, 0.09) and pos.scaling.k_in != neg.scaling.k_in
    v, f = BETWEEN_SATURATIONS.T
    np.testing.assert_allclose(literal_asym.force(v), f, rtol=1e-13)
    # the Stribeck part at v = 0 is that of v >= 0 (F(0+) = sum f_s = 44 N), for v < 0 the other's
    assert float(literal_asym.stribeck(0.0)) == pytest.approx(44.0, rel=1e-14)
    assert float(literal_asym.stribeck(-0.075)) == pytest.approx(23.723784996648185 - 34.5 * 0.075, rel=1e-13)
    bound = max(float32_bound(table1_curve("gauss"), impl),
                float32_bound(table1_curve("exponential", SCALED_TABLE1, 1 / 57.2, 0.09), impl))
    assert np.max(np.abs(force_f32(literal_asym, v, impl) - f)) <= bound
    codegen.emit(literal_asym, tmp_path, "fl", activation_impl=impl)
    c = parity.c_forces(build_model(tmp_path, "fl", build_dir=tmp_path / "build"), "fl", v)
    assert np.max(np.abs(c.astype(float) - f)) <= bound
