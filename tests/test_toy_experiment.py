"""An experiment is added in one place: a toy experiment registered in this file, with a claims
file and a figure script of its own (written here into temporary copies of ``data/chapter`` and
``paper_figures``) and a rule of its own, goes through the memory check, ``glamas.reproduce``, the ledger and
``glamas.verify`` without an edit of any library module."""

import dataclasses
import json
import textwrap
from dataclasses import dataclass

import numpy as np
import pytest

from glamas import claims, ledger, memory, reproduce, verdict_rules, verify
from glamas.experiments import registry
from glamas.experiments.registry import Experiment, register


@dataclass(frozen=True)
class CoinConfig:
    """A coin tossed ``iterations`` times in each of ``runs`` runs."""

    runs: int = 3
    iterations: int = 100

    def memory_bytes(self) -> int:
        return self.runs * self.iterations * memory.BYTES_PER_VALUE


@dataclass(frozen=True)
class CoinResult:
    config: CoinConfig
    tosses: np.ndarray
    """(runs, iterations): 1 for heads."""


def run(config: CoinConfig, seed: int = 0, workers=None, progress=None) -> CoinResult:
    tosses = np.random.default_rng(seed).integers(0, 2, (config.runs, config.iterations)).astype(float)
    return CoinResult(config=config, tosses=tosses)


def claim_rows(result: CoinResult, config: CoinConfig) -> list[dict]:
    return claims.verdicts(claims.load("coin"), {"heads_share": float(result.tosses.mean())})


CLAIMS = {"claims": {"coin": [{"id": "fair_coin", "where": "nowhere", "chapter": "a coin is fair", "kind": "inferred",
                               "why": "a toy", "rule": "coin_share", "metric": "heads_share", "op": "<",
                               "threshold": 0.6}]}}
SCRIPT = '''
    """A toy figure: the share of heads per run."""

    from glamas import errors, figures
    from glamas.experiments import registry


    def main(argv=None):
        with figures.figure(registry.REGISTRY["coin"], "coin_figure", __doc__, argv) as (ax, result, config):
            ax.plot(result.tosses.mean(axis=1), "o")


    if __name__ == "__main__":
        errors.run(main)
'''


@pytest.fixture()
def coin(tmp_path, monkeypatch):
    """The toy experiment registered, its claims and its script in temporary copies of the repository's places."""
    (tmp_path / "chapter").mkdir()
    (tmp_path / "chapter" / "coin.json").write_text(json.dumps(CLAIMS))
    (tmp_path / "scripts").mkdir()
    (tmp_path / "scripts" / "coin_figure.py").write_text(textwrap.dedent(SCRIPT))
    monkeypatch.setattr(claims, "DATA", tmp_path)
    monkeypatch.setitem(verdict_rules.RULES, "coin_share", verdict_rules.Rule(
        "coin_share", "a coin falls heads at most so often", "learning curves", r"^heads_share$"))
    monkeypatch.setattr(reproduce, "SCRIPTS", tmp_path / "scripts")
    experiment = register(Experiment("coin", CoinConfig, run, lambda runs, iterations: CoinConfig(runs, iterations),
                                     CoinConfig.runs, CoinConfig.iterations, CoinResult, claim_rows=claim_rows,
                                     figures=("coin_figure",), chapter=False))
    yield experiment
    registry.REGISTRY.pop("coin")


def test_a_toy_experiment_goes_through_memory_reproduce_ledger_and_verify(coin, tmp_path, monkeypatch):
    assert "coin_figure" in registry.figure_scripts(chapter_only=False) and "coin.npz" in registry.result_files()
    assert memory.check(CoinConfig()) == 3 * 100 * 8
    for side in ("committed", "recomputed"):
        out, results = tmp_path / side / "figures", tmp_path / side / "results"
        reproduce.run(["coin_figure"], ["--out", str(out), "--results", str(results)])
        assert (results / "coin.npz").is_file() and (out / "coin_figure.png").is_file()
    table = ledger.markdown("coin", results_dir=tmp_path / "committed" / "results")
    assert "`fair_coin`" in table and "| reproduced |" in table
    monkeypatch.setattr(verify, "RESULTS", tmp_path / "committed" / "results")
    monkeypatch.setattr(verify, "FIGURES", tmp_path / "committed" / "figures")
    assert verify.differences(tmp_path / "recomputed") == []  # the same seed gives the same files
    (tmp_path / "recomputed" / "figures" / "coin_figure.png").write_bytes(b"not a figure")
    assert verify.differences(tmp_path / "recomputed") == ["figures/coin_figure.png: differs from the committed figure: its bytes differ"]


def test_a_second_experiment_of_a_registered_name_is_refused_naming_both(coin):
    from glamas.experiments import gridworld
    with pytest.raises(ValueError, match=r"an experiment named 'gridworld' is registered already \(by "
                                         r"glamas\.experiments\.gridworld\.experiment\); \S*test_toy_experiment must "
                                         "choose another name"):
        register(dataclasses.replace(coin, name="gridworld"))
    assert registry.REGISTRY["gridworld"] is gridworld.EXPERIMENT
