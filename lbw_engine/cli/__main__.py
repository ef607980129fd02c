import sys

from lbw_engine.cli import main

sys.exit(main())
