"""Validation: analytic reference solutions (:mod:`.reference`), ready-made
cases and the measures that compare them with the solver (:mod:`.cases`)."""
