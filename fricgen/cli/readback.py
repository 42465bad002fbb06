"""``fricgen readback DUMP --model MODEL -o OUT``: the parameters the firmware adapted
(``fric_adapt_export``'s text) read back into a model.json (``fricgen.control.readback``)."""
from __future__ import annotations

import numpy as np

from ..control.readback import model_from_dump, parse_dump
from ..control.regressor import parameter_names, trained_parameters
from ..errors import DataError, ModelError
from .common import add_model, add_output, say, write_file
from .inputs import load_model


def register(p) -> None:
    """The arguments of this command."""
    p.add_argument("dump", help="the text fric_adapt_export wrote (fricgen-adapt-dump 2, or 1)")
    add_model(p, help="the model.json the firmware was emitted from (emit --adapt)")
    add_output(p, "the adapted model.json to write")
    p.set_defaults(run=run)


def run(args) -> int:
    model = load_model(args.model, "readback")
    try:
        with open(args.dump, encoding="utf-8") as stream:
            text_read = stream.read()
    except UnicodeDecodeError:
        raise DataError(f"{args.dump}: not UTF-8 text") from None
    adapted = model_from_dump(model, text_read)
    try:                          # what eval, emit and diagnose will check when they load it
        text = adapted.checked_json()
    except ModelError as exc:
        raise ModelError(f"{args.dump}: the adapted parameters make a model that cannot be used: "
                         f"{exc}") from None
    path = write_file(args, text, inputs=(args.model, args.dump))
    before, (_, after, scale) = trained_parameters(model), parse_dump(text_read)
    moved = ", ".join(f"{n} {b:.7g} -> {a:.7g}" for n, b, a in zip(parameter_names(model), before, after)
                      if a != float(np.float32(b))) or "none (the trained values, to float32)"
    say(f"fricgen: read back {after.size} adapted parameters into {path} (model "
        f"{adapted.model_hash}); changed: {moved}"
        + ("" if scale == 1.0 else f"; times the controller's k_hat {scale:.7g} (the friction "
                                   "the loop applies)"))
    return 0
