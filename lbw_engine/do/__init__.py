"""Doing (Sec. VII): instantiate a learned plan in a new workspace and verify the result.

Pure logic over data, no perception imports (tests/test_boundaries.py):

* ``plan.load`` / ``plan.parse`` — plan.json for execution;
* ``lbw_engine.rules.commands`` — rules/commands.yaml (Table IX), validated;
* ``matching.match_initial_state`` — Sec. VII-A initial-state matching;
* ``lbw_engine.model.env.EnvModel`` — the environment model, also execution's expected state;
* ``tracing.trace`` — walk the plan, find goals, expand commands (Table IX), with
  ``jaws`` / ``grasp`` (which way the jaws close, where they grip), ``fine`` (a place
  into side contact: ALIGN's slide, or a push), ``clearing`` (blocks that start
  stacked on a picked one are set aside) and ``balance`` ($parallel order, steadied
  placements);
* ``listing.format_commands`` — commands.txt (Fig. 24);
* ``verification.verify`` — the final structure against the expected one.

The CLI (``lbw execute``) wires these to the cameras, the object-finder and
the robot in ``perception``.
"""
