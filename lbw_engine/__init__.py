"""lbw_engine: the generic interpreter of learning by watching.

Everything the paper hand-codes as knowledge lives in rules/; this package
executes it. Nothing here imports from ``perception``: the command-line entry
point (``lbw_engine.cli``) is the only place that wires a perception-backed
detector registry into the interpreter.
"""

__version__ = "0.1.0"
