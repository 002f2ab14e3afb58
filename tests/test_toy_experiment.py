"""An experiment is added in one place: a toy experiment's package (its face, experiment, analysis
and plots modules), written here into a temporary directory on the path of :mod:`glamas.experiments`,
with a claims file and a figure script of its own (written into temporary copies of ``data/chapter``
and ``paper_figures``) and a rule of its own, is found, registered and handed on without a list
naming it, and goes through the small runs, the memory check, ``glamas.reproduce``, the ledger and
``glamas.verify`` without an edit of any library module."""

import dataclasses
import json
import sys
import textwrap

import pytest

import glamas.experiments
from glamas import claims, committed, ledger, memory, reproduce, small_runs, verdict_rules, verify
from glamas.experiments import registry
from glamas.experiments.registry import register

PACKAGE = {
    "__init__.py": '''
        """A coin tossed in runs: a toy experiment."""

        from glamas.experiments.coin.analysis import claim_rows
        from glamas.experiments.coin.experiment import CoinConfig, CoinResult, run
        from glamas.experiments.faces import face
        from glamas.experiments.registry import Experiment, register

        __getattr__, __dir__ = face(__name__, __file__)

        EXPERIMENT = register(Experiment("coin", CoinConfig, run, lambda runs, iterations: CoinConfig(runs, iterations),
                                         result=CoinResult, claim_rows=claim_rows, figures=("coin_figure",),
                                         chapter=False, small_run={"runs": 2, "iterations": 10}))
    ''',
    "experiment.py": '''
        from dataclasses import dataclass

        import numpy as np

        from glamas import memory


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
    ''',
    "analysis.py": '''
        from glamas import claims


        def heads_share(result) -> float:
            return float(result.tosses.mean())


        def claim_rows(result, config) -> list[dict]:
            return claims.verdicts(claims.load("coin"), {"heads_share": heads_share(result)})
    ''',
    "plots.py": '''
        def plot_tosses(ax, result):
            ax.plot(result.tosses.mean(axis=1), "o")
    ''',
}
CLAIMS = {"claims": {"coin": [{"id": "fair_coin", "where": "nowhere", "chapter": "a coin is fair", "kind": "inferred",
                               "why": "a toy", "rule": "coin_share", "metric": "heads_share", "op": "<",
                               "threshold": 0.6}]}}
SCRIPT = '''
    """A toy figure: the share of heads per run."""

    from glamas import errors, figures
    from glamas.experiments import coin


    def main(argv=None):
        with figures.figure(coin.EXPERIMENT, "coin_figure", __doc__, argv) as (ax, result, config):
            coin.plot_tosses(ax, result)


    if __name__ == "__main__":
        errors.run(main)
'''


@pytest.fixture()
def coin(tmp_path, monkeypatch):
    """The toy experiment's package on the path of glamas.experiments, its claims and its script in
    temporary copies of the repository's places; the experiment as the registry finds it."""
    (tmp_path / "packages" / "coin").mkdir(parents=True)
    for name, source in PACKAGE.items():
        (tmp_path / "packages" / "coin" / name).write_text(textwrap.dedent(source))
    (tmp_path / "chapter").mkdir()
    (tmp_path / "chapter" / "coin.json").write_text(json.dumps(CLAIMS))
    (tmp_path / "scripts").mkdir()
    (tmp_path / "scripts" / "coin_figure.py").write_text(textwrap.dedent(SCRIPT))
    monkeypatch.setattr(glamas.experiments, "__path__", [*glamas.experiments.__path__, str(tmp_path / "packages")])
    monkeypatch.setattr(claims, "DATA", tmp_path)
    monkeypatch.setitem(verdict_rules.RULES, "coin_share", verdict_rules.Rule(
        "coin_share", "a coin falls heads at most so often", "learning curves", r"^heads_share$"))
    monkeypatch.setattr(reproduce, "SCRIPTS", tmp_path / "scripts")
    monkeypatch.setattr(committed, "SCRIPTS_OF", dict(committed.SCRIPTS_OF))  # registering fills it
    assert "coin" not in registry.REGISTRY
    yield next(experiment for experiment in registry.experiments() if experiment.name == "coin")
    registry.REGISTRY.pop("coin")
    for module in [name for name in sys.modules if name.startswith("glamas.experiments.coin")]:
        del sys.modules[module]


def test_a_toy_experiment_package_is_found_handed_on_and_has_its_small_run(coin):
    face = sys.modules["glamas.experiments.coin"]
    assert face.EXPERIMENT is coin and (coin.runs, coin.iterations, coin.counts) == (3, 100, "iterations")
    assert face.heads_share is sys.modules["glamas.experiments.coin.analysis"].heads_share
    assert "glamas.experiments.coin.plots" not in sys.modules and callable(face.plot_tosses)
    assert small_runs.sizes()["coin"] == {"runs": 2, "iterations": 10}
    assert len(small_runs.small_digest("coin")) == 64


def test_a_toy_experiment_goes_through_memory_reproduce_ledger_and_verify(coin, tmp_path, monkeypatch):
    assert "coin_figure" in registry.figure_scripts(chapter_only=False) and "coin.npz" in registry.result_files()
    assert memory.check(coin.paper_scale()) == 3 * 100 * 8
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
                                         r"glamas\.experiments\.gridworld\.experiment\); glamas\.experiments\.coin\."
                                         r"experiment must "
                                         "choose another name"):
        register(dataclasses.replace(coin, name="gridworld"))
    assert registry.REGISTRY["gridworld"] is gridworld.EXPERIMENT
