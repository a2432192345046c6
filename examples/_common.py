"""Shared by the numbered examples: where figures go (argv[1], else $IMPACT_EXAMPLES_OUT,
else ./example-figures) and a non-interactive matplotlib."""
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))


def out_dir() -> Path:
    folder = Path(
        sys.argv[1] if len(sys.argv) > 1 else os.environ.get("IMPACT_EXAMPLES_OUT", "example-figures")
    )
    folder.mkdir(parents=True, exist_ok=True)
    return folder
