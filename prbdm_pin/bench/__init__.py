"""Error against cost: fitted nR PRBDMs beside hand-built finite-segment chains and the FE truth.

For every beam of a :class:`BenchConfig` this measures

- **fitted nR models** (``fit(..., stiffness="joint", objective="eigen")``: joint parametrisation,
  eigen objective on the straight pose, N = n frequencies): fit wall time, the error of each of the
  first n bending frequencies against the plate truth (``compute_truth``, default level, cached);
- **finite-segment chains** (N equal segments, half segments at both ends so that the springs sit
  at the segment centres, K = ``finite_segment_stiffness``), the model a user builds by hand;
- for both: the tip error at load indices P L^2 / (E I_root) (default 1e-3, 1, 5) against the
  inextensible elastica (``truth.elastica.elastica_static``: exact for slender strips, a few
  per cent off for wide plates, whose plate-bending stiffness it ignores), relative to the elastica
  tip displacement; the dynamic error (tip step response over 1 s and tip FRF, both by modal
  superposition, :mod:`prbdm_pin.simulation.response`, against the truth's modes with 2 % modal
  damping); the
  simulation cost (process CPU time of ``simulate`` per simulated second, step tip load, default
  integrator and step);
- **the FE truth** at several plate mesh levels: CPU time of the modal solve and frequency error
  against the finest level run;
- optionally a **MuJoCo peer**: the fitted nR model exported as an MJCF hinge chain
  (``export.mjcf_text``), its frequencies from MuJoCo's own mass matrix and joint stiffness, its
  cost from ``mj_step`` at the exporter's default time step with MuJoCo's default Euler
  integrator (MuJoCo imported lazily).

The harness behind ``prbdm bench``, apart from the library it measures: ``config`` (what a run
covers and the frozen rows it returns), ``run`` (the measurements), ``report`` (frontier,
Markdown table, raw JSON) and ``plot`` (the log-log figure with the non-dominated frontier).
"""

