"""Real rigs nobody here recorded: fricgen's default against the textbook fit and the published models.

For every dataset folder of ../shared/data that is present (a missing one is skipped with one line):
  - ur10e: per joint, the default trained on jointJ_train.csv (a log: t, dq, tau, read as a
    user's file through --columns); scored on jointJ_test.csv (M a + F(v) + o), on the other
    trajectory jointJ_heldout_ptp.csv and on its cruise points jointJ_sweep_ptp.csv (F(v) + o:
    the rigid body removed there already);
  - panda: per joint, trained on jointJ_train.csv with its ddq_est as the log's acceleration
    (``--columns a=ddq_est``: the file's torque is the measured one less the published rigid-body
    model evaluated at it), scored on jointJ_test.csv (M a + F(v) + o); then again without that
    column, and with both logs on a uniform time grid (``panda_on_a_uniform_grid``);
  - kinova_gen3: the sweep, trained on sweep_train.csv (weighted by its F_std and n), scored on
    sweep_test.csv; and the runs: the five run_v*_train.csv logs joined end to end (t restarts at
    0 in each) trained as one log, scored on the five test runs (M a + F(v) + o) over all their
    samples and over their steady parts (t >= 0.5 s), as the folder's baseline.py scores them;
  - emps: the log DATA_EMPS.mat (force = gtau vir), trained on its first 70 % in time and scored
    on the rest (M a + F(v) + o).
Beside each: the textbook fit, per-direction Coulomb + viscous by ordinary least squares with the
inertia where the data hold it (the folder's baseline.py), and the published model where there is
one; v and a of the scores come from each folder's own filter (its baseline's), the same for every
model, over samples with |v| above the folder's threshold. Ratios are the default's RMS error over
the textbook's and over the published model's; beside the first, its 90 % interval from a
moving-block bootstrap of the scored rows (``ratio_interval``): what the test data can tell.

Run: python benchmarks/real_data.py [--data ../shared/data]
"""
import argparse
import contextlib
import io
import time
from pathlib import Path

import numpy as np
from scipy.io import loadmat
from scipy.signal import butter, filtfilt

import fricgen
from fricgen.data.table import read_table_csv

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
VMIN = 0.01


def rms(e):
    return float(np.sqrt(np.mean(np.square(e))))


def basis(v):
    p, n = v > 0, v < 0
    return np.column_stack([p * 1.0, p * v, -1.0 * n, n * v])


def textbook(v, a, tau, inertia=True):
    """Per-direction Coulomb + viscous (+ inertia) least squares; a predictor of (v, a)."""
    cols = [basis(v)] + ([a[:, None]] if inertia else [])
    theta, *_ = np.linalg.lstsq(np.column_stack(cols), tau, rcond=None)
    return lambda v, a: np.column_stack([basis(v)] + ([a[:, None]] if inertia else [])) @ theta


def trained(columns, rotary=True):
    """fricgen's default on the columns, silent, a robot joint's in rad, rad/s, Nm (as its q, dq,
    tau columns would name it); (predictor of (v, a), what it chose, seconds, the inertia)."""
    start = time.process_time()
    with contextlib.redirect_stderr(io.StringIO()):
        report = fricgen.train(columns, warn=lambda line: None, rotary=rotary)
    seconds = time.process_time() - start
    model, ident = report.model, report.identification
    mass = ident.body.inertia if ident is not None else 0.0   # a residual inertia may be < 0
    offset = report.training["axis"]["offset"] or 0.0
    chose = report.law.name if report.law is not None else report.training["method"]
    return (lambda v, a: model.force(v) + mass * a + offset), chose, seconds, mass


def csv(path):
    return read_table_csv(path, (), keep_extra=True)


def log_columns(d, acceleration=None):
    """A joint log's t, v and force, and its ``acceleration`` column as a, where named."""
    return {"t": d["t"], "v": d["dq"], "force": d["tau"],
            **({} if acceleration is None else {"a": d[acceleration]})}


def ratio_interval(fit_res, tb_res, resamples=2000, blocks=50):
    """The 90 % interval of rms(fit_res) / rms(tb_res): a moving-block bootstrap of the rows (at
    most ``blocks`` blocks of consecutive rows, so a log's correlated neighbours move together;
    one row per block for a sweep's few points), with a fixed seed."""
    n = fit_res.size
    size = max(1, n // blocks)
    starts = np.random.default_rng(0).integers(0, n - size + 1, (resamples, -(-n // size)))
    idx = (starts[:, :, None] + np.arange(size)).reshape(resamples, -1)[:, :n]
    ratios = np.sqrt(np.mean(fit_res[idx] ** 2, axis=1) / np.mean(tb_res[idx] ** 2, axis=1))
    return np.percentile(ratios, [5, 95])


def row(name, fit_res, tb_res, pub_err, chose, extra=""):
    """One line: the default's and the textbook's RMS error (from their residuals), their ratio
    with its 90 % interval, the published model's RMS error and the ratio to it."""
    fit_err, tb_err = rms(fit_res), rms(tb_res)
    lo, hi = ratio_interval(np.asarray(fit_res), np.asarray(tb_res))
    pub = f"{pub_err:8.4f} {fit_err / pub_err:6.3f}" if pub_err is not None else f"{'-':>8s} {'-':>6s}"
    print(f"{name:22s} {fit_err:8.4f} {tb_err:8.4f} {fit_err / tb_err:6.3f} {lo:5.2f}-{hi:4.2f} {pub} {chose}{extra}")
    return fit_err / tb_err, (fit_err / pub_err if pub_err else None), lo


def load_baseline(folder):
    """The folder's baseline.py as a module (its filter and published constants)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(f"baseline_{folder.name}", folder / "baseline.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def joint_log(b, folder, j, test_name, acceleration=None):
    """Joint j's default and textbook fit, both trained on jointJ_train.csv (the default with
    its ``acceleration`` column, where named), and the moving samples of ``test_name`` through
    the folder's own filter ``b.va``: (predict, textbook, what the default chose, a note, v, a,
    tau) of those samples."""
    tr = csv(folder / f"joint{j + 1}_train.csv")
    predict, chose, sec, mass = trained(log_columns(tr, acceleration))
    v, a = b.va(tr["t"], tr["dq"])
    m = np.abs(v) > b.VMIN
    tb = textbook(v[m], a[m], tr["tau"][m])
    te = csv(folder / test_name.format(j + 1))
    v, a = b.va(te["t"], te["dq"])
    m = np.abs(v) > b.VMIN
    return predict, tb, chose, f" (m {mass:.3g}, {sec:.2f} s CPU)", v[m], a[m], te["tau"][m]


def per_joint(name, joints, score):
    """``score(j)`` for each joint, a refused one reported with one line and the rest scored."""
    for j in range(joints):
        try:
            score(j)
        except fricgen.FricgenError as exc:
            print(f"{name} J{j + 1}: REFUSED: {exc}")


def ur10e(folder, ratios):
    b = load_baseline(folder)

    def score(j):
        predict, tb, chose, note, v, a, y = joint_log(b, folder, j, "joint{}_test.csv")
        pub = b.fric_pub(j, v) + b.PUB_MJJ[j] * a
        ratios.append(row(f"ur10e J{j + 1} test", y - predict(v, a), y - tb(v, a),
                          rms(y - pub), chose, note))
        ho = csv(folder / f"joint{j + 1}_heldout_ptp.csv")
        v, _ = b.va(ho["t"], ho["dq"])
        m = np.abs(v) > b.VMIN
        y, zero = ho["tau"][m], np.zeros(int(m.sum()))
        ratios.append(row(f"ur10e J{j + 1} ptp", y - predict(v[m], zero), y - tb(v[m], zero),
                          rms(y - b.fric_pub(j, v[m])), chose))
        sw = csv(folder / f"joint{j + 1}_sweep_ptp.csv")
        zero = np.zeros(sw["v"].size)
        ratios.append(row(f"ur10e J{j + 1} sweep", sw["f"] - predict(sw["v"], zero),
                          sw["f"] - tb(sw["v"], zero), rms(sw["f"] - b.fric_pub(j, sw["v"])), chose))
    per_joint("ur10e", 6, score)


def panda(folder, ratios):
    b = load_baseline(folder)

    def score(j):
        predict, tb, chose, note, v, a, y = joint_log(b, folder, j, "joint{}_test.csv", "ddq_est")
        pub = min(rms(y - b.sigmoid(j, v)), rms(y - b.linear(j, v)))
        ratios.append(row(f"panda J{j + 1}", y - predict(v, a), y - tb(v, a), pub, chose, note))
    per_joint("panda", 7, score)


def panda_without_acceleration(folder):
    """The panda scores again with the default trained on t, dq and tau alone: the inertia
    against the derivative of its own smoothed v."""
    b = load_baseline(folder)
    print("\npanda without its acceleration column (default / textbook):")
    for j in range(7):
        predict, tb, _, note, v, a, y = joint_log(b, folder, j, "joint{}_test.csv")
        print(f"panda J{j + 1} (t, dq, tau)   {rms(y - predict(v, a)) / rms(y - tb(v, a)):6.3f}{note}")


def uniform_grid(d):
    """A jointJ_*.csv on the uniform grid of its median time step (every column linearly
    interpolated: as ``fricgen.train`` reads a log whose time stamps jitter)."""
    t = d["t"]
    grid = np.arange(t[0], t[-1], float(np.median(np.diff(t))))
    return {"t": grid, "dq": np.interp(grid, t, d["dq"]), "tau": np.interp(grid, t, d["tau"])}


def panda_on_a_uniform_grid(folder):
    """The panda scores again with train and test logs on a uniform time grid (``uniform_grid``),
    the folder's filter then applied there, the textbook refitted there: the folder's own
    scores filter v over the sample index of jittering time stamps and differentiate it over
    the stamps, an acceleration other than that of the logs' uniform resampling."""
    b = load_baseline(folder)
    print("\npanda again on a uniform time grid (default / textbook):")
    for j in range(7):
        tr = uniform_grid(csv(folder / f"joint{j + 1}_train.csv"))
        predict, *_ = trained(log_columns(tr))
        v, a = b.va(tr["t"], tr["dq"])
        m = np.abs(v) > b.VMIN
        tb = textbook(v[m], a[m], tr["tau"][m])
        te = uniform_grid(csv(folder / f"joint{j + 1}_test.csv"))
        v, a = b.va(te["t"], te["dq"])
        m = np.abs(v) > b.VMIN
        y, v, a = te["tau"][m], v[m], a[m]
        print(f"panda J{j + 1} (uniform grid) {rms(y - predict(v, a)) / rms(y - tb(v, a)):6.3f}")


def kinova(folder, ratios):
    tr, te = csv(folder / "sweep_train.csv"), csv(folder / "sweep_test.csv")
    start = time.process_time()
    report = fricgen.train({"v": tr["v"], "f": tr["f"], "f_std": tr["f_std"], "n": tr["n"]},
                           warn=lambda line: None, rotary=True)
    sec = time.process_time() - start
    fc_fv, *_ = np.linalg.lstsq(np.column_stack([np.ones_like(tr["v"]), tr["v"]]), tr["f"], rcond=None)
    tb = fc_fv[0] + fc_fv[1] * te["v"]
    ratios.append(row("kinova sweep", te["f"] - report.model.force(te["v"]), te["f"] - tb,
                      None, report.law.name, f" ({sec:.2f} s CPU)"))
    b = load_baseline(folder)
    logs = {part: [csv(path) for path in sorted(folder.glob(f"run_v*_{part}.csv"))]
            for part in ("train", "test")}
    joined = {name: np.concatenate([log_columns(d)[name] for d in logs["train"]])
              for name in ("t", "v", "force")}               # t restarts at 0 in every run
    predict, chose, sec, mass = trained(joined)
    filtered = [(d["t"], *b.va(d["t"], d["dq"]), d["tau"]) for d in logs["train"]]
    v, a, y = (np.concatenate([f[k][f[1] > b.VMIN] for f in filtered]) for k in (1, 2, 3))
    tb = textbook(v, a, y)
    for name, steady in (("all", 0.0), ("steady", 0.5)):
        parts = [(d["t"], *b.va(d["t"], d["dq"]), d["tau"]) for d in logs["test"]]
        keep = [(f[1] > b.VMIN) & (f[0] >= steady) for f in parts]
        v, a, y = (np.concatenate([f[k][m] for f, m in zip(parts, keep)]) for k in (1, 2, 3))
        ratios.append(row(f"kinova runs {name}", y - predict(v, a), y - tb(v, a), None,
                          chose, f" (m {mass:.3g}, {sec:.2f} s CPU)" if not steady else ""))


def emps(folder, ratios):
    d = loadmat(folder / "DATA_EMPS.mat")
    t, qm = d["t"].ravel(), d["qm"].ravel()
    force = float(d["gtau"].ravel()[0]) * d["vir"].ravel()
    cut = int(0.7 * t.size)
    predict, chose, sec, mass = trained({"t": t[:cut], "x": qm[:cut], "force": force[:cut]}, rotary=False)
    ts = float(np.median(np.diff(t)))
    bb, aa = butter(4, 100.0 / (0.5 / ts))
    q = filtfilt(bb, aa, qm)
    v = np.gradient(q, ts)
    a = np.gradient(v, ts)
    m = np.abs(v) > VMIN * 0.1
    train = m & (np.arange(t.size) < cut)
    test = m & (np.arange(t.size) >= cut)
    tb = textbook(v[train], a[train], force[train] - 0.0)
    cols = lambda v, a: np.column_stack([a, v, np.sign(v), np.ones_like(v)])
    theta, *_ = np.linalg.lstsq(cols(v[train], a[train]), force[train], rcond=None)
    y = force[test]
    ratios.append(row("emps (last 30 %)", y - predict(v[test], a[test]), y - tb(v[test], a[test]),
                      rms(y - cols(v[test], a[test]) @ theta), chose,
                      f" (m {mass:.4g}, {sec:.2f} s CPU; 'published' = IDIM-LS refitted)"))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path, default=DATA)
    args = p.parse_args()
    print(f"{'dataset':22s} {'default':>8s} {'textbook':>8s} {'ratio':>6s} {'90 % int.':>9s} {'publish.':>8s} "
          f"{'ratio':>6s} chose")
    ratios = []
    for name, run in (("ur10e", ur10e), ("panda", panda), ("kinova_gen3", kinova), ("emps", emps)):
        folder = args.data / name
        if not folder.is_dir():
            print(f"{name}: skipped, no folder {folder}")
            continue
        try:
            run(folder, ratios)
        except fricgen.FricgenError as exc:
            print(f"{name}: REFUSED: {exc}")
    tb = np.array([r[0] for r in ratios])
    pub = np.array([r[1] for r in ratios if r[1] is not None])
    if not tb.size:
        print(f"\nno dataset scored: none of the folders is in {args.data} (--data names the folder)")
        return
    above = [r for r in ratios if r[2] > 1.0]
    print(f"\n{len(tb)} scores: default / textbook worst {tb.max():.3f}, median {np.median(tb):.3f} "
          f"({len(above)} with its 90 % interval above 1)"
          + (f"; default / published worst {pub.max():.3f}, median {np.median(pub):.3f}" if pub.size else ""))
    if (args.data / "panda").is_dir():
        panda_without_acceleration(args.data / "panda")
        panda_on_a_uniform_grid(args.data / "panda")


if __name__ == "__main__":
    main()
