"""``python -m cadcog`` runs the command-line interface."""

import sys

from cadcog.cli import console_main

sys.exit(console_main())
