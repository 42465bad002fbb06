"""fricgen: multisource friction models trained in Python, emitted as fixed-size C."""
__version__ = "0.1.0"

from .friction import FrictionSource, MultisourceFriction, multisource, preset  # noqa: E402
from .data import Sweep, Dataset, Scaling, prepare, read_sweep_csv, synthesize_benchmark  # noqa: E402
from .elm import ELMRegressor, ElmNetwork  # noqa: E402
from .model import FrictionModel, ModelError  # noqa: E402

__all__ = ["__version__", "FrictionSource", "MultisourceFriction", "multisource", "preset",
           "Sweep", "Dataset", "Scaling", "prepare", "read_sweep_csv", "synthesize_benchmark",
           "ELMRegressor", "ElmNetwork", "FrictionModel", "ModelError"]
