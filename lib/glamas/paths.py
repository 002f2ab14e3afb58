"""Where the repository keeps its data (chapter parameters, claims, maps, reference results)."""

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "data"
RESULTS = DATA / "results"
MAPS = DATA / "maps"
