"""Adaptive backstepping position control with friction compensation (section 6), in Python and
as the C runtime through cffi, and the closed loops that compare compensation variants."""
