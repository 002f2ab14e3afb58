"""The claim ledger: docs/ledger.md and README.md's count of verdicts match the committed results,
and --check/--write work."""

import subprocess
import sys

import pytest

from glamas import claims, ledger

README = f"# title\n\n{ledger.START}\nold count\n{ledger.END}\n\n## next\n"
HEADER = "| experiment | claim | verdict |\n|---|---|---|"
TABLE = "\n".join([HEADER, "| a | `x` | reproduced |", "| a | `y` | **NOT reproduced** |",
                   "| b | `z` | **undecidable** (the interval \\| contains 1) |", "| b | `w` | reproduced |"])


def test_the_ledger_and_the_readme_count_match_the_committed_results():
    done = subprocess.run([sys.executable, "-m", "glamas.ledger", "--check"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_count_gives_every_verdict_and_links_the_ledger():
    assert ledger.verdict_count(TABLE) == ("4 claims: 2 reproduced, 1 not reproduced, 1 undecidable — "
                                           "see [the claim ledger](docs/ledger.md).")
    assert ledger.verdict_count(HEADER).startswith("0 claims: 0 reproduced, 0 not reproduced, 0 undecidable")
    with pytest.raises(ValueError, match="has no verdict"):
        ledger.verdict_count(HEADER + "\n| a | `x` | maybe |")


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
    monkeypatch.setattr(ledger, "markdown", lambda *experiments: TABLE)
    return readme, page


def test_write_writes_the_page_and_the_count_and_check_then_passes(files):
    readme, page = files
    assert ledger.main(["--write"]) == 0
    assert page.read_text() == ledger.page(TABLE)
    assert readme.read_text() == README.replace("old count", ledger.verdict_count(TABLE))
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
