"""``lbw export PLAN.json --to pddl|hddl|bt|dot --out DIR``: the learned plan for other tools.

Writes (design.md "Command line"): ``domain.pddl`` + ``problem.pddl`` (pddl),
``domain.hddl`` + ``problem.hddl`` (hddl), ``tree.yaml`` (bt: a py_trees tree
as data; ``lbw execute PLAN.json SCENARIO --via bt`` runs it), ``plan.dot``
(dot). Staged with OutputDir: exit 2 on bad input leaves no file. See
docs/export.md.
"""

from __future__ import annotations

import argparse

from lbw_engine.do import plan as planmod
from lbw_engine.outputs import OutputDir
from lbw_engine.paths import default_rules_dir

HELP = "export a learned plan as PDDL, HDDL, a behaviour tree (YAML) or a Graphviz picture"
EXIT_CODES = ("0 the files were written; 2 bad input (one line: file, place, what is wrong); "
              "3 internal error")


def add_arguments(p: argparse.ArgumentParser) -> None:
    """PLAN.json, --to, --out DIR, --rules DIR."""
    from lbw_engine.export import FORMATS

    p.add_argument("plan", metavar="PLAN.json", help="plan.json written by `lbw analyze`")
    p.add_argument("--to", required=True, choices=sorted(FORMATS), metavar="FORMAT",
                   help=f"the format: {', '.join(sorted(FORMATS))}")
    p.add_argument("--out", metavar="DIR", required=True, help="output directory")
    p.add_argument("--rules", metavar="DIR", default=None,
                   help="rules folder (default: the bundled rules/)")


def run(args: argparse.Namespace) -> int:
    """Load the plan and rules, write the format's files."""
    from lbw_engine import export

    rules = export.load(args.rules or default_rules_dir())
    plan = planmod.load(args.plan)
    with OutputDir(args.out) as out:
        written = export.write(plan, args.to, out, rules)
    print(f"lbw export: wrote {' and '.join(str(p) for p in written)}")
    return 0
