"""Evaluation and presentation of a run: sequence metrics, benchmark tables, the HTML report.

Nothing here needs the simulator: inputs are actions.json, plan.json and the
ground truth passed in as plain lists (the caller computes it from perception).
"""
