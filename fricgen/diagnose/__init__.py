"""Where simulation and measurement disagree: the force residual, the named effects that explain
it, the held-out gap before and after, and the report."""
