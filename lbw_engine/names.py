"""The names design.md reserves: the worktable, the demonstrator's hand, the world.

A scenario may not name an object ``table`` or ``hand``; actions.json and
plan.json use them for the table and the hand. They are declared once, here.
"""

TABLE = "table"
HAND = "hand"
WORLD = "world"
RESERVED = frozenset({TABLE, HAND})
