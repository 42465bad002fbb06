"""Simulated axes: the motor axis of eq. (18) of section 6 and its integrators (``axis``), its
force law from a friction curve and named effects (``effect_law``), references and synthesized
motion logs."""
