"""What a selection records: the candidates of a step and the decision about each effect set."""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional

from ..effects import EFFECTS, Effect


@dataclass
class Candidate:
    """One candidate of one selection step: its cross-validated residual on the fit part."""
    effect: str
    mse: float


@dataclass
class Step:
    """One effect considered in the forward selection, fitted jointly with those chosen before,
    and the decision about it. ``p_value``: of the held-out test (``decision``); ``share``: the
    fraction of the held-out residual's sum of squares it removes; ``size``: the RMS of its
    own force there (in the joint fit), relative to the RMS friction force; ``gap_before``/``gap_after``:
    the held-out gap without and with it; ``reason``: why it was refused ('' if added)."""
    effect: str
    fitted: Optional[Effect]
    joint: List[Effect]
    p_value: float
    n_effective: float
    share: float
    size: float
    gap_before: float
    gap_after: float
    added: bool
    reason: str
    candidates: List[Candidate]

    @property
    def beside(self) -> List[str]:
        """The effects fitted jointly with this one: the context of its decision."""
        return [e.name for e in self.joint if e is not self.fitted]

    @property
    def label(self) -> str:
        """The effect, and for a refused one the effects it was fitted with: 'e (with a, b)'."""
        return self.effect if self.added or not self.beside else f"{self.effect} (with {', '.join(self.beside)})"

    @property
    def gain(self) -> float:
        """Relative reduction of the held-out gap, 1 - after / before."""
        return 1.0 - self.gap_after / self.gap_before if self.gap_before > 0 else 0.0

    def summary(self) -> dict:
        return {"effect": self.effect, "parameters": self.fitted.parameters() if self.fitted else {},
                "p_value": self.p_value, "share": self.share, "size": self.size, "gap_before": self.gap_before,
                "gap_after": self.gap_after, "held_out_gain": self.gain,
                "named": self.effect in EFFECTS}

