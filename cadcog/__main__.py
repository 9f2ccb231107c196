"""``python -m cadcog`` runs the command-line interface."""

import sys

from cadcog.cli import main

sys.exit(main())
