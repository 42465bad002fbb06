"""A sweep whose Coulomb + viscous curves determine nothing holds no friction: refused in one
line (``training.trainer.check_sweep_friction``), as a log's is."""
import numpy as np
import pytest

import fricgen
from fricgen.cli import main
from fricgen.errors import DataError


def swapped_stribeck_sweep():
    """A forward Stribeck sweep of 10 log-spaced speeds with its columns v and f swapped."""
    speed = np.geomspace(0.001, 0.3, 10)
    force = 0.5 + 0.4 * np.exp(-(speed / 0.02) ** 2) + 0.6 * speed
    return {"v": force, "f": speed}


def test_a_swapped_one_way_sweep_is_refused_in_one_line(tmp_path, capsys):
    """It had trained F_c 0.064 +- 0.17 N and F_v 0 +- 0.24 N s/m, a model that explains nothing."""
    columns = swapped_stribeck_sweep()
    np.savetxt(tmp_path / "s.csv", np.column_stack([columns["v"], columns["f"]]), delimiter=",",
               header="v,f", comments="")
    assert main(["train", str(tmp_path / "s.csv"), "-o", str(tmp_path / "m.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds no friction" in err[0] and "swapped" in err[0]
    assert not (tmp_path / "m.json").exists()


@pytest.mark.parametrize("points", [3, 5, 10])
def test_a_small_noisy_sweep_of_real_friction_trains(points):
    rng = np.random.default_rng(1000 + points)
    speed = np.geomspace(0.01, 0.5, points)
    v = np.concatenate([speed, -speed])
    f = np.sign(v) * (0.3 + 2.0 * np.abs(v)) + 0.05 * rng.standard_normal(v.size)
    assert fricgen.train({"v": v, "f": f}, warn=lambda line: None).model is not None


def test_the_refusal_is_a_data_error_in_the_api():
    with pytest.raises(DataError, match="holds no friction"):
        fricgen.train(swapped_stribeck_sweep(), warn=lambda line: None)
