"""Simulated axes: the controlled axis of section 6, the stick-slip truth axis, references and
synthesized motion logs."""
