"""Progress of long steps reaches a callback (the CLI's stderr), throttled, and never stdout."""
import numpy as np

from fricgen import _progress
from fricgen._progress import Progress
from fricgen.data import Sweep
from fricgen.fit import ELMRegressor
from fricgen.fit.directions import CV_FOLDS, fit_directions
from fricgen.fit.elm import EnlargedScheme
from fricgen.friction import preset


def test_a_quick_step_is_silent_and_a_long_one_is_told_with_its_seconds(monkeypatch):
    heard = []
    quick = Progress(heard.append)
    quick("step 1 of 2")
    assert heard == []                                       # within PROGRESS_SECONDS: silent
    Progress(None)("nobody listens")                         # no callback: nothing, no error
    monkeypatch.setattr(_progress, "PROGRESS_SECONDS", 0.0)
    told = Progress(heard.append)
    told("step 1 of 2")
    told("step 2 of 2")
    assert [line.rsplit(" (", 1)[0] for line in heard] == ["step 1 of 2", "step 2 of 2"]
    assert all(line.endswith(" s)") for line in heard)


def test_the_symmetry_cross_validation_tells_each_fold(monkeypatch, capsys):
    rng = np.random.default_rng(0)
    v = np.concatenate([rng.uniform(-0.2, -1e-3, 300), rng.uniform(1e-3, 0.2, 300)])
    sweep = Sweep(v, np.sign(v) * preset("paper3")(np.abs(v)) + rng.uniform(-0.5, 0.5, v.size))
    elm = ELMRegressor(n_hidden=10, scheme=EnlargedScheme(w_max=30.0), solver="loo", random_state=0)
    monkeypatch.setattr(_progress, "PROGRESS_SECONDS", 0.0)
    heard = []
    told = fit_directions(sweep, elm, vs_max=0.02, progress=heard.append)
    assert [line.split(" (")[0] for line in heard] == ["symmetry: fitted on all rows"] + [
        f"symmetry: cross-validated {k} of {CV_FOLDS} folds" for k in range(1, CV_FOLDS + 1)]
    assert told.cv_rmse == fit_directions(sweep, elm, vs_max=0.02).cv_rmse
    assert capsys.readouterr() == ("", "")
