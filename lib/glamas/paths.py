"""Where the repository keeps its data (chapter parameters, claims, maps, reference results) and
its figures."""

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "data"
RESULTS = DATA / "results"
MAPS = DATA / "maps"
SCRIPTS = REPO / "paper_figures"
"""The figure scripts, one per figure."""
FIGURES = SCRIPTS / "output"
"""The committed figures the scripts draw at their paper-scale defaults."""
