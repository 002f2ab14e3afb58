"""The claim ledger: docs/ledger.md and README.md's count of verdicts match the committed results,
and --check/--write work."""

import math
import subprocess
import sys

import pytest

from glamas import claims, ledger

README = f"# title\n\n{ledger.START}\nold count\n{ledger.END}\n\n## next\n"


def _claim(id, kind="chapter", where="Sec. 5.3, Fig. 11a", source=""):
    return claims.Claim(id=id, where=where, chapter=f"{id} holds (ours)", kind=kind, why="w", metric=id, rule="growth",
                        op=">", threshold=0.0, source=source)


def _rows():
    """Ledger rows of every verdict and every source, one turning on a reading."""
    chapter = [_claim("x"), _claim("y"), _claim("z"), _claim("f", where="Sec. 4.2, Fig. 6")]
    inferred = [_claim("i", kind="inferred"), _claim("r", kind="inferred", source="Kok and Vlassis 2004")]
    field = [_claim("p", kind="field", where="ICAART 2011", source="ICAART 2011")]
    measured = {"x": 1.0, "y": -1.0, "z": math.nan, "f": 1.0, "i": 1.0, "r": 1.0, "p": -1.0}
    rows = claims.verdicts(chapter + inferred + field, measured, readings={"other": {"f": -1.0}})
    return [("gridworld" if row["claim"].id != "f" else "state_encoding", row) for row in rows]


ROWS = _rows()
TABLE = ledger.table(ROWS)


@pytest.mark.long
def test_the_ledger_and_the_readme_summary_match_the_committed_results():
    done = subprocess.run([sys.executable, "-m", "glamas.ledger", "--check"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_summary_counts_by_source_and_names_the_chapter_claims_that_fail():
    text = ledger.summary(ROWS)
    assert "- the chapter's own: 4; 1 reproduced, 1 not reproduced, 1 undecidable, 1 turn on a reading or choice" \
        in text
    assert "- inferred by us: 2; 2 reproduced, 0 not reproduced, 0 undecidable, 0 turn on a reading or choice" in text
    assert "- from the field's papers: 1; 0 reproduced, 1 not reproduced, 0 undecidable, 0 turn on a reading or " \
           "choice" in text
    assert " ".join(ledger.MARKS.split()) in " ".join(text.split())
    named = [line for line in text.splitlines() if line.startswith("- ") and "holds" in line]
    assert [line.split(" holds")[0] for line in named] == ["- y", "- z", "- f"]
    assert "turns on a reading or choice (1 of 2 hold: holds at the default reading, not at other)" \
        in " ".join(text.split())
    assert "[the claim ledger](docs/ledger.md)" in text


def test_the_figure_table_judges_each_figure_on_its_own_claims():
    text = ledger.summary(ROWS)
    fig11 = next(line for line in text.splitlines() if line.startswith("| Fig. 11 "))
    # r reads another source: not counted here
    assert "| 1 of 3 chapter claims reproduced; 1 of 1 inferred claim reproduced |" in fig11
    fig6 = next(line for line in text.splitlines() if line.startswith("| Fig. 6 "))
    assert "| 0 of 1 chapter claim reproduced (1 turns on a choice) |" in fig6


def test_every_chapter_claim_tests_exactly_one_of_the_figures():
    rows = [(experiment, {"claim": claim}) for experiment in ledger.with_claims()
            for claim in claims.load(experiment) if claim.kind == "chapter"]
    for experiment, row in rows:
        on = [figure.name for figure in ledger.FIGURES if row in ledger.on_figure(figure, [(experiment, row)])]
        assert len(on) == 1, (row["claim"].id, on)


def test_the_ledger_labels_each_claim_by_its_source():
    assert "| the chapter |" in TABLE and "| inferred by us |" in TABLE
    assert "| inferred by us from Kok and Vlassis 2004 |" in TABLE and "| ICAART 2011 |" in TABLE


def test_the_ledger_page_is_a_title_a_sentence_and_the_table():
    title, sentence, table = ledger.page(TABLE).split("\n\n")
    assert title == "# Claim ledger"
    assert sentence.count(". ") == 0 and sentence.endswith(".")
    assert table == TABLE + "\n"


@pytest.fixture
def files(monkeypatch, tmp_path):
    """README.md and docs/ledger.md in ``tmp_path``, the ledger's table TABLE."""
    readme, page = tmp_path / "README.md", tmp_path / "docs" / "ledger.md"
    readme.write_text(README)
    monkeypatch.setattr(ledger, "README", readme)
    monkeypatch.setattr(ledger, "LEDGER", page)
    monkeypatch.setattr(ledger, "rows", lambda *experiments: ROWS)
    return readme, page


def test_write_writes_the_page_and_the_count_and_check_then_passes(files):
    readme, page = files
    assert ledger.main(["--write"]) == 0
    assert page.read_text() == ledger.page(TABLE)
    assert readme.read_text() == README.replace("old count", ledger.summary(ROWS))
    assert ledger.main(["--check"]) == 0


@pytest.mark.parametrize("stale", ["README.md", "ledger.md", "both"])
def test_check_reports_a_stale_readme_or_page_in_one_line(files, capsys, stale):
    readme, page = files
    ledger.main(["--write"])
    if stale in ("README.md", "both"):
        readme.write_text(README)
    if stale in ("ledger.md", "both"):
        page.unlink()
    capsys.readouterr()
    assert ledger.main(["--check"]) == 1
    out = capsys.readouterr().out.strip()
    assert out.count("\n") == 0
    assert all(name in out for name in ("README.md", "ledger.md") if stale in (name, "both"))


def test_the_readme_needs_one_pair_of_markers():
    with pytest.raises(ValueError, match="one <!-- verdicts:start -->"):
        ledger.readme_with("count", "no markers here")
    with pytest.raises(KeyError, match="no experiment with claims named \\['nonexistent'\\]"):
        ledger.markdown("nonexistent")


def test_every_experiment_with_claims_has_a_ledger_entry():
    assert set(ledger.with_claims()) == set(claims.experiments())
