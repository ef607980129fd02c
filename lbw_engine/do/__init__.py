"""Doing (Sec. VII): instantiate a learned plan in a new workspace and verify the result.

Pure logic over data, no perception imports (tests/test_boundaries.py):

* ``plan.load`` / ``plan.parse`` — plan.json for execution;
* ``commandrules.load_dir`` — rules/commands.yaml (Table IX), validated;
* ``matching.match_initial_state`` — Sec. VII-A initial-state matching;
* ``lbw_engine.model.env.EnvModel`` — the environment model, also execution's expected state;
* ``tracing.trace`` — walk the plan, find goals, expand commands (Table IX);
* ``verification.verify`` — the final structure against the expected one.

The CLI (``lbw execute``) wires these to the cameras, the object-finder and
the robot in ``perception``.
"""
